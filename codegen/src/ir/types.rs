//! The IR's types: one drive, resolved, ordered and typed, as plain serialisable data.
//!
//! Every emitter reads only these types. They hold facts (numbers, names, enums, the
//! runtime's own layout and frame-meaning values), never prose built for people: the
//! Markdown emitter words ranges, meanings and layouts itself.

pub use crate::parse::model::PrintedRejection;
pub use crate::parse::model::{
    BitOrder, Duplex, InferredFact, Synchronisation, TimingField, Topology,
    WarningModel as WarningIr,
};
use serde::Serialize;
use vfd_runtime::meaning::FrameMeaning;
use vfd_runtime::serial::Parity;
use vfd_runtime::units::Unit;
use vfd_runtime::{
    Access, AddressMap, CommandKind, DataType, DecodeErrorKind, FrameLayout, PreStep, Space,
    TakesEffect,
};

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

/// The drive's serial ports, resolved to register codes.
#[derive(Debug, Clone, Serialize)]
pub struct PortsIr {
    /// Manual sections.
    pub source: String,
    /// Remarks.
    pub note: String,
    /// The ports, in file order.
    pub ports: Vec<PortIr>,
    /// Codes of the registers both ports share.
    pub shared: Vec<String>,
    /// Registers that exist once per port: each row holds one code per port, in port order.
    pub registers: Vec<Vec<String>>,
}

/// One serial port.
#[derive(Debug, Clone, Serialize)]
pub struct PortIr {
    /// Identifier (`two_wire`).
    pub id: String,
    /// Rust name of its constant (`TWO_WIRE`).
    pub const_name: String,
    /// English name.
    pub name: String,
    /// Chinese name.
    pub name_zh: String,
    /// The registers setting it: (what they set, register code), sorted by the first.
    pub settings: Vec<(String, String)>,
}

/// A scale chosen by another register.
#[derive(Debug, Clone, Serialize)]
pub struct ScaleByIr {
    /// Code of the selector register.
    pub register: String,
    /// One choice per selector value.
    pub choices: Vec<ScaleChoiceIr>,
    /// The scale and range for every selector value `choices` does not list (its `value`
    /// is unused: 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub otherwise: Option<ScaleChoiceIr>,
}

/// The scale and range a register has for one selector value.
#[derive(Debug, Clone, Serialize)]
pub struct ScaleChoiceIr {
    /// The selector's value.
    pub value: u32,
    /// Engineering value of one raw step.
    pub scale: f64,
    /// Lowest raw value.
    pub raw_min: i64,
    /// Highest raw value.
    pub raw_max: i64,
}

/// A formula of the manual, parsed.
#[derive(Debug, Clone, Serialize)]
pub struct ConversionIr {
    /// Identifier (the function's name).
    pub id: String,
    /// What the result is.
    pub name: String,
    /// Manual section.
    pub source: String,
    /// The formula as written.
    pub formula: String,
    /// The formula in postfix order, as the runtime evaluates it.
    pub program: Vec<vfd_runtime::conversion::Op>,
    /// The inputs, in argument order.
    pub inputs: Vec<ConversionInputIr>,
    /// The result's unit.
    pub unit: Unit,
    /// Code of the register the result belongs to, if any.
    pub result: Option<String>,
    /// The result is cut to a whole number.
    pub truncate: bool,
    /// The selector register (code) and value it applies for (`None` value: nonzero).
    pub when: Option<(String, Option<u32>)>,
    /// Remarks.
    pub note: String,
    /// Worked examples: input values in argument order, and the result.
    pub examples: Vec<(Vec<f64>, f64, String)>,
}

/// One input of a conversion.
#[derive(Debug, Clone, Serialize)]
pub struct ConversionInputIr {
    /// Its name in the formula and as an argument.
    pub name: String,
    /// Code of the register it comes from, if any.
    pub register: Option<String>,
    /// The factor applied to the register's value first.
    pub times: f64,
    /// What it is, when it is no register.
    pub description: String,
}

/// A bit of a bit-field word, resolved: its id, mask and the level at which it acts.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct BitRefIr {
    /// The bit's id in its bit field.
    pub id: String,
    /// The bit's mask in the word.
    pub mask: u32,
    /// It acts when it is 0.
    pub active_low: bool,
    /// Id of the register holding the bit, when it is not the word of its role
    /// (`register.field`, or a coil of its own).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub register: Option<String>,
}

/// A number, or the current value of a register (by id).
#[derive(Debug, Clone, Serialize, PartialEq)]
#[serde(rename_all = "snake_case")]
pub enum AmountIr {
    /// A constant.
    Number(f64),
    /// The register with this id.
    Register(String),
}

/// The behaviour model, resolved: register ids and bit masks.
#[derive(Debug, Clone, Serialize)]
pub struct BehaviourIr {
    /// Manual sections.
    pub source: String,
    /// What the model assumes.
    pub note: String,
    /// Id of the command-word register.
    pub command_register: String,
    /// Bits that must all act for the command word to act.
    pub command_require: Vec<BitRefIr>,
    /// Run bit (none when the command register holds codes).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub run: Option<BitRefIr>,
    /// Command codes, when the command register holds a code rather than bits.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub command_codes: Option<CommandCodesIr>,
    /// Reverse-run bit, beside the (forward) run bit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub run_reverse: Option<BitRefIr>,
    /// Reverse bit.
    pub reverse: Option<BitRefIr>,
    /// Fault-reset bit.
    pub reset: Option<BitRefIr>,
    /// Fault reset by a value written to a register: its id and the raw value.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reset_by_write: Option<(String, u32)>,
    /// Coast-stop bit.
    pub coast: Option<BitRefIr>,
    /// The mode register (id) and the raw values in which commands are taken.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub require_mode: Option<(String, Vec<u32>)>,
    /// Id of the frequency-command register.
    pub frequency_command: String,
    /// Command-word bits that make the frequency command effective.
    pub frequency_require: Vec<BitRefIr>,
    /// Acceleration time (seconds per span).
    pub acceleration: AmountIr,
    /// Deceleration time (seconds per span).
    pub deceleration: AmountIr,
    /// The change the ramp times refer to.
    pub span: AmountIr,
    /// Monitors showing the output.
    pub output: Vec<String>,
    /// Monitors showing the frequency command in use.
    pub reference: Vec<String>,
    /// Output current model: monitors, value at zero output, value at the span.
    pub current: Option<(Vec<String>, f64, f64)>,
    /// The output current at and above which the drive reports an overload.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub current_overload: Option<AmountIr>,
    /// The output frequency at and above which the drive reports the frequency detected.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frequency_detection: Option<AmountIr>,
    /// The frequency a percentage frequency command's 100 % stands for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frequency_percent_of: Option<AmountIr>,
    /// Status-word registers.
    pub status_registers: Vec<String>,
    /// Status bits: running, reverse, at reference, tripped, enabled, always.
    pub status: StatusBitsIr,
    /// A register showing the state as a code.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub status_state: Option<StatusStateIr>,
    /// Registers showing the present trip code.
    pub trip_code: Vec<String>,
    /// Trip-history slots, newest first.
    pub trip_history: Vec<TripSlotIr>,
    /// A value written to a register (id, raw value) that clears the trip history.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub trip_clear_by_write: Option<(String, u32)>,
    /// Process words: control, reference, status, output register ids.
    pub process: Option<[String; 4]>,
    /// Error codes per protocol id.
    pub refusals: Vec<RefusalsIr>,
}

/// One place of a trip history: a whole register (by id), or a field of a bit-field
/// register.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum TripSlotIr {
    /// The whole register, by id.
    Register(String),
    /// A field of a bit-field register.
    Field {
        /// Register id.
        register: String,
        /// Field id.
        field: String,
        /// The field's bits in the word.
        mask: u32,
    },
}

/// Command codes: the raw values of the command register, by what they do.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct CommandCodesIr {
    /// Run forward.
    pub run: Vec<u32>,
    /// Run in reverse.
    pub run_reverse: Vec<u32>,
    /// Stop (ramp down).
    pub stop: Vec<u32>,
    /// Coast to a stop.
    pub coast: Vec<u32>,
    /// Reset a trip.
    pub reset: Vec<u32>,
}

/// A register showing the drive's state as a code.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct StatusStateIr {
    /// Register id.
    pub register: String,
    /// Value while stopped.
    pub stopped: u32,
    /// Value while running forward.
    pub forward: u32,
    /// Value while running in reverse.
    pub reverse: u32,
    /// Value while tripped.
    pub tripped: u32,
}

/// The status bits of a behaviour model.
#[derive(Debug, Clone, Serialize, Default)]
pub struct StatusBitsIr {
    /// Set while running.
    pub running: Vec<BitRefIr>,
    /// Set while reverse.
    pub reverse: Vec<BitRefIr>,
    /// Set while running forward.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub forward: Vec<BitRefIr>,
    /// Set while running at the reference.
    pub at_reference: Vec<BitRefIr>,
    /// Set while tripped.
    pub tripped: Vec<BitRefIr>,
    /// Set while the output current is at or above the overload level.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub overload: Vec<BitRefIr>,
    /// Set while running at or above the detection frequency.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub frequency_detected: Vec<BitRefIr>,
    /// Set unless coasting.
    pub enabled: Vec<BitRefIr>,
    /// Always set.
    pub always: Vec<BitRefIr>,
}

/// Error codes one protocol answers refused requests with (`None`: silence).
#[derive(Debug, Clone, Serialize)]
pub struct RefusalsIr {
    /// Protocol id.
    pub protocol: String,
    /// No register at that number.
    pub unknown_register: Option<u16>,
    /// Write to a read-only register.
    pub read_only: Option<u16>,
    /// Value out of range.
    pub out_of_range: Option<u16>,
    /// Write that cannot be made while running.
    pub while_running: Option<u16>,
    /// Write outside the required mode.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wrong_mode: Option<u16>,
    /// Bad checksum.
    pub bad_checksum: Option<u16>,
    /// A character no frame of the protocol carries.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bad_character: Option<u16>,
    /// A frame that cannot be read otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub malformed: Option<u16>,
    /// The code after too many consecutive unreadable frames, and how many are allowed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub retries_exceeded: Option<(u16, AmountIr)>,
}

/// Line-level facts of the serial link; `None` where the description does not say.
#[derive(Debug, Clone, Default, Serialize)]
pub struct LineIr {
    /// Manual section.
    pub source: String,
    /// Half or full duplex.
    pub duplex: Option<Duplex>,
    /// Who controls the line.
    pub topology: Option<Topology>,
    /// Character synchronisation.
    pub synchronisation: Option<Synchronisation>,
    /// Bit order within a character.
    pub bit_order: Option<BitOrder>,
}

/// Serial line facts.
#[derive(Debug, Clone, Serialize)]
pub struct SerialIr {
    /// Manual section.
    pub source: String,
    /// Remarks.
    pub note: String,
    /// Supported baud rates.
    pub baud_rates: Vec<u32>,
    /// Supported parities.
    pub parities: Vec<Parity>,
    /// The data bits the drive can use (one when fixed; `[7, 8]` when a setting chooses).
    pub data_bits: Vec<u8>,
    /// The character formats a setting offers each protocol (from the code tables whose
    /// values set the line and choose a protocol), the factory one marked; other
    /// protocols speak the defaults below.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub protocol_lines: Vec<ProtocolLineIr>,
    /// Stop bits the drive sends.
    pub stop_bits_sent: u8,
    /// Stop bits the drive needs.
    pub stop_bits_received: u8,
    /// The stop bits the drive can be set to, when they are its choice (`[1, 2]`); empty:
    /// fixed as `stop_bits_sent` and `stop_bits_received`.
    pub stop_bits: Vec<u8>,
    /// Factory baud rate.
    pub default_baud: u32,
    /// Factory parity.
    pub default_parity: Parity,
    /// Factory data bits.
    pub default_data_bits: u8,
    /// Factory stop bits.
    pub default_stop_bits: u8,
    /// Silence after power-on, in ms.
    pub startup_delay_ms: u64,
    /// A frame not complete within this many ms is dropped.
    pub frame_abandon_ms: u64,
    /// Time the drive may take to start answering, in ms.
    pub processing_allowance_ms: u64,
    /// Timings that are placeholders or assumptions, not the manual's.
    pub assumed_timing: Vec<TimingField>,
    /// Line-level facts, when the description gives any.
    pub line: Option<LineIr>,
}

/// A character format a setting offers a protocol.
#[derive(Debug, Clone, Serialize)]
pub struct ProtocolLineIr {
    /// The protocol's id.
    pub protocol: String,
    /// Data bits.
    pub data_bits: u8,
    /// Parity.
    pub parity: Parity,
    /// Stop bits.
    pub stop_bits: u8,
    /// The code of the register whose value chooses it, and that value.
    pub selector: String,
    /// See `selector`.
    pub value: u16,
    /// The selector's factory value chooses it.
    pub factory: bool,
}

/// Station numbers.
#[derive(Debug, Clone, Serialize)]
pub struct AddressingIr {
    /// Lowest station number.
    pub min: u8,
    /// Highest station number.
    pub max: u8,
    /// Remarks.
    pub note: String,
    /// Id of the register holding the station number.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub register: Option<String>,
}

/// A protocol file (`protocols/<id>.yaml`): its frame layouts, shared by every drive that
/// uses it.
#[derive(Debug, Clone, Serialize)]
pub struct ProtocolFileIr {
    /// File id (`toshiba-ascii`).
    pub id: String,
    /// Rust name of its module of layouts (`toshiba_ascii`).
    pub module: String,
    /// English name.
    pub name: String,
    /// Chinese name.
    pub name_zh: String,
    /// What it is.
    pub description: String,
    /// Whether frames are text.
    pub text: bool,
    /// Every layout a command or the error reply uses, by name, in the file's order.
    pub layouts: Vec<FrameLayout>,
    /// The protocol file it is `based_on`, read with it (an input of the build, not part
    /// of the snapshot: the layouts above are already merged).
    #[serde(skip)]
    pub based_on: Option<String>,
}

/// A protocol as one drive speaks it.
#[derive(Debug, Clone, Serialize)]
pub struct ProtocolIr {
    /// Id within the drive (`ascii`).
    pub id: String,
    /// Rust name of its `static` (`ASCII`).
    pub const_name: String,
    /// The protocol file it uses (`toshiba-ascii`).
    pub uses: String,
    /// Manual section.
    pub source: String,
    /// English name.
    pub name: String,
    /// Commands, with their layouts named.
    pub commands: Vec<CommandIr>,
    /// Name of the error-reply layout, when the protocol has error replies.
    pub error_reply: Option<String>,
    /// A lower-case command letter in a reply means "tripped".
    pub lowercase_means_tripped: bool,
    /// Longest frame in bytes.
    pub max_frame_len: u16,
    /// Station numbers this drive accepts.
    pub address_range: (u8, u8),
    /// Optional parts requests include by default.
    pub default_optional_parts: Vec<String>,
    /// Steps some requests need first.
    pub pre_steps: Vec<PreStep>,
    /// Process words sent when the caller gives none, as the protocol file states them
    /// (`None`: it states none, and 0000h 0000h are sent).
    pub default_process: Option<[u16; 2]>,
    /// Silence between frames, in character times.
    pub frame_gap_chars: f32,
    /// The most registers one read carries (1: one per read).
    pub max_words_per_read: u16,
    /// The most registers one write carries (1: one per write).
    pub max_words_per_write: u16,
    /// A read or write of several registers skips the registers it cannot access.
    pub partial_blocks: bool,
    /// What a block transfer writes and reads on this drive (`None`: no block transfer).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub block: Option<vfd_runtime::BlockSpec>,
    /// The manual sections and the note of the drive's `block:` (empty without one).
    #[serde(skip_serializing_if = "String::is_empty")]
    pub block_source: String,
    /// See `block_source`.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub block_note: String,
    /// The drive's timing rules beyond the gap in characters.
    pub timing: vfd_runtime::serial::LinkTiming,
    /// The drive's entry states `before_start` (the manual says what bytes before a
    /// frame's start do); `false`: `timing.before_start` is the library's default, which
    /// the page marks assumed.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub before_start_stated: bool,
    /// The drive's broadcast rule, when it takes broadcasts over this protocol.
    pub broadcast: Option<vfd_runtime::broadcast::BroadcastRule>,
    /// Registers with their own numbers on the wire in this protocol.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub wire_numbers: Vec<vfd_runtime::protocol::WireNumber>,
    /// Parameters reached through pages on this protocol.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub paging: Option<vfd_runtime::protocol::Paging>,
    /// What the description says of its pages for people: the manual section, the name of
    /// each range, what is assumed and the note.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pages_doc: Option<PagesDocIr>,
    /// The drive's persistence selector, as the runtime protocol carries it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub persistence: Option<vfd_runtime::PersistenceSelector>,
    /// The table its error replies are named from.
    pub error_table: ErrorTableIr,
    /// The protocol's variants, the register selecting one and the mismatch error.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub variants: Option<vfd_runtime::variant::Variants>,
    /// The error code the drive answers a function it lacks with, and where the manual
    /// says so (`protocols[].unsupported_function`); `None`: the manual does not say.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unsupported_function: Option<UnsupportedFunctionIr>,
}

/// What a drive answers to a function it lacks.
#[derive(Debug, Clone, Serialize)]
pub struct UnsupportedFunctionIr {
    /// The error code of the reply.
    pub error_code: u16,
    /// The manual section saying so.
    pub source: String,
}

/// Where a protocol's error replies take their meaning from.
#[derive(Debug, Clone, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ErrorTableIr {
    /// The drive's own table ([`DriveIr::error_codes`]), which applies to this protocol.
    Drive,
    /// The protocol file's own table (empty when it has none): the drive's does not apply.
    Protocol(ErrorCodesIr),
}

/// One command of a protocol.
#[derive(Debug, Clone, Serialize)]
pub struct CommandIr {
    /// The code on the wire (letter, AK nibble, function code; 0 when the layout has none).
    pub code: u32,
    /// What it does.
    pub kind: CommandKind,
    /// Data types it carries (empty: any).
    pub data_types: Vec<DataType>,
    /// Address space.
    pub space: Space,
    /// Register number to wire number.
    pub address_map: AddressMap,
    /// Request layout, by name.
    pub request: String,
    /// Reply layout, by name.
    pub reply: String,
    /// Codes a normal reply may carry (empty: the request's).
    pub reply_codes: Vec<u32>,
    /// The code an error reply to it carries, where the error layout allows several.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error_code: Option<u32>,
    /// Never answered (`reply: none`).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub no_reply: bool,
    /// Used only when a request names its code (`extra: true`).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub extra: bool,
    /// A lower-case code in the request says the sender has tripped.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub lowercase_means_sender_tripped: bool,
    /// The registers it may address (numbers before the address map; empty: any).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub registers: Vec<u16>,
    /// Its data is a percentage of this register (code), this many % per raw step; a
    /// receiving drive applies the first of these conversions that holds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub percent_of: Option<(String, f64, Vec<String>)>,
    /// The master's follow-up to its replies: the layouts (by name) sent after a sound and
    /// after a garbled reply.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub follow_up: Option<(String, String)>,
    /// A plain write whose storage is the instruction's (`storage: by_instruction`).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub stored_by_instruction: bool,
}

/// The people's side of a protocol's pages (`protocols[].pages`).
#[derive(Debug, Clone, Serialize)]
pub struct PagesDocIr {
    /// Manual section.
    pub source: String,
    /// Each range's name, in the order of the ranges.
    pub range_names: Vec<String>,
    /// Keys the description assumes (`initial`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub assumed: Vec<String>,
    /// Note.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub note: String,
}

/// The manual's error codes.
#[derive(Debug, Clone, Serialize)]
pub struct ErrorCodesIr {
    /// Manual section.
    pub source: String,
    /// Ids of the protocols whose error replies carry these codes.
    pub protocols: Vec<String>,
    /// The codes.
    pub codes: Vec<ErrorCodeIr>,
    /// Conditions under which the drive stays silent.
    pub silent: Vec<String>,
}

/// One error code.
#[derive(Debug, Clone, Serialize)]
pub struct ErrorCodeIr {
    /// The code.
    pub code: u16,
    /// Identifier.
    pub id: String,
    /// Rust variant name.
    pub variant: String,
    /// English name.
    pub name: String,
    /// Chinese name.
    pub name_zh: String,
    /// The manual's explanation.
    pub meaning: String,
    /// The code as the manual prints it (`H0C`), from its table's `notation`; empty when
    /// the table states none.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub printed: String,
}

/// A code table.
#[derive(Debug, Clone, Serialize)]
pub struct CodeTableIr {
    /// Identifier.
    pub id: String,
    /// Rust type name.
    pub type_name: String,
    /// English name.
    pub name: String,
    /// Chinese name.
    pub name_zh: String,
    /// Manual section.
    pub source: String,
    /// Whether the manual lists every value (only then is it a Rust enum).
    pub exhaustive: bool,
    /// Remarks.
    pub note: String,
    /// The values.
    pub values: Vec<CodeValueIr>,
}

/// One value of a code table.
#[derive(Debug, Clone, Serialize)]
pub struct CodeValueIr {
    /// The value.
    pub value: u16,
    /// Identifier.
    pub id: String,
    /// Rust variant name.
    pub variant: String,
    /// English name.
    pub name: String,
    /// Chinese name.
    pub name_zh: String,
    /// What it sets on the line: the baud rate and the parts of the character format.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub line: Option<LineSettingIr>,
    /// The id of the protocol it chooses.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub protocol: Option<String>,
}

/// What a code value sets on the line; each part `None` where it sets nothing of it.
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Eq)]
pub struct LineSettingIr {
    /// The baud rate.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub baud: Option<u32>,
    /// Data bits per character.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub data_bits: Option<u8>,
    /// Parity.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub parity: Option<vfd_runtime::serial::Parity>,
    /// Stop bits.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stop_bits: Option<u8>,
}

impl LineSettingIr {
    /// The whole character format (data bits, parity, stop bits), when it sets all of it.
    pub fn format(&self) -> Option<(u8, vfd_runtime::serial::Parity, u8)> {
        Some((self.data_bits?, self.parity?, self.stop_bits?))
    }
}

/// A bit-field layout of a word.
#[derive(Debug, Clone, Serialize)]
pub struct BitfieldIr {
    /// Identifier.
    pub id: String,
    /// Rust type name.
    pub type_name: String,
    /// English name.
    pub name: String,
    /// Chinese name.
    pub name_zh: String,
    /// Manual section.
    pub source: String,
    /// Remarks.
    pub note: String,
    /// Codes of the registers whose value it is.
    pub registers: Vec<String>,
    /// Fields, in file order.
    pub fields: Vec<BitIr>,
    /// Worked examples.
    pub examples: Vec<BitExampleIr>,
}

impl BitfieldIr {
    /// Bits the manual marks reserved.
    pub fn reserved_mask(&self) -> u16 {
        self.fields
            .iter()
            .filter(|f| f.reserved)
            .fold(0, |mask, f| mask | f.mask())
    }
}

/// One field of a bit-field word.
#[derive(Debug, Clone, Serialize)]
pub struct BitIr {
    /// Identifier (`reserved_<lsb>` for unnamed reserved bits).
    pub id: String,
    /// Rust accessor name.
    pub method: String,
    /// Lowest bit.
    pub lsb: u8,
    /// Width in bits.
    pub width: u8,
    /// Reserved by the manual.
    pub reserved: bool,
    /// English name.
    pub name: String,
    /// Chinese name.
    pub name_zh: String,
    /// Meaning of 0.
    pub zero: String,
    /// Meaning of 1.
    pub one: String,
    /// Chinese meaning of 0.
    pub zero_zh: String,
    /// Chinese meaning of 1.
    pub one_zh: String,
    /// Code table giving the meanings of a multi-bit field's values.
    pub code_table: Option<String>,
    /// Remarks.
    pub note: String,
}

impl BitIr {
    /// The field's bits within the word.
    pub fn mask(&self) -> u16 {
        (((1u32 << self.width) - 1) << self.lsb) as u16
    }
}

/// A worked bit-field example.
#[derive(Debug, Clone, Serialize)]
pub struct BitExampleIr {
    /// The word.
    pub value: u16,
    /// Ids of the fields it sets.
    pub set: Vec<String>,
    /// Multi-bit fields and their values, by id.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub fields: Vec<(String, u16)>,
    /// The manual's words.
    pub description: String,
    /// Manual section.
    pub source: String,
}

/// How a register's value is typed in Rust.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(tag = "kind", content = "type", rename_all = "snake_case")]
pub enum ValueKind {
    /// A runtime quantity type, by name (`Hertz`).
    Quantity(String),
    /// A generated code-table enum, by type name.
    CodeTable(String),
    /// A generated bit-field word, by type name.
    Bitfield(String),
    /// A plain unsigned word.
    Raw,
    /// A plain signed word.
    RawSigned,
    /// A plain number with a scale other than 1.
    Scaled,
    /// A plain unsigned double word.
    RawDouble,
    /// A plain signed double word.
    RawSignedDouble,
    /// Text.
    Text,
}

/// One end of a register's range.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BoundIr {
    /// The static bound, in raw steps.
    pub raw: i64,
    /// Code of the register that sets this bound at run time (`FH`), if any.
    pub register: Option<String>,
}

/// A register (or parameter, or coil).
#[derive(Debug, Clone, Serialize)]
pub struct RegisterIr {
    /// Number before any protocol's address map.
    pub address: u16,
    /// Identifier.
    pub id: String,
    /// Rust type name.
    pub type_name: String,
    /// The manual's code (`FH`, `FA01`, `3-03`).
    pub code: String,
    /// Other names the manual gives it (`P.33`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub aliases: Vec<String>,
    /// English name.
    pub name: String,
    /// Chinese name.
    pub name_zh: String,
    /// The manual's description.
    pub description: String,
    /// Remarks.
    pub note: String,
    /// Engineering unit.
    pub unit: Unit,
    /// Engineering value of one raw step.
    pub scale: f64,
    /// Two's-complement signed.
    pub signed: bool,
    /// Lowest accepted value; `None` when the manual gives no range.
    pub min: Option<BoundIr>,
    /// Highest accepted value; `None` when the manual gives no range.
    pub max: Option<BoundIr>,
    /// Factory default, in engineering units.
    pub default: Option<f64>,
    /// Access over the serial link.
    pub access: Access,
    /// Writes go to RAM only.
    pub ram_only: bool,
    /// A persistent write is accepted but stored in RAM only.
    pub persistent_write_to_ram: bool,
    /// May be written while the motor runs (false when the manual does not say).
    pub writable_while_running: bool,
    /// The manual does not say whether it may be written while running (`unknown`): a
    /// master attempts the write and reports a refusal; the virtual drive accepts it.
    pub while_running_unknown: bool,
    /// Only effective when set from the panel.
    pub panel_only: bool,
    /// When a written value takes effect.
    pub takes_effect: TakesEffect,
    /// Shape on the wire.
    pub data_type: DataType,
    /// Address space.
    pub space: Space,
    /// Number of array elements (0: not an array).
    pub array_len: u8,
    /// How the value is typed in Rust.
    pub value: ValueKind,
    /// Id of the code table naming its values (complete or not), if any.
    pub code_table: Option<String>,
    /// Manual section.
    pub source: String,
    /// Facts inferred by the description, not stated by the manual.
    pub inferred: Vec<InferredFact>,
    /// Safety warnings about this register.
    pub warnings: Vec<WarningIr>,
    /// Writes to it are never answered.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub no_reply: bool,
    /// The manual gives it no number of its own: its protocols reach it by its wire numbers
    /// only, and `address` is a number no frame carries.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub wire_only: bool,
    /// Its place on pages as the description gives it (`on_page`): protocol id, page,
    /// offset.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub on_page: Vec<(String, u16, u16)>,
    /// Code of the live register whose value this one holds from the last trip.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub held_at_trip_of: Option<String>,
    /// Code of the other register at its address, when two share it (one read-only, one
    /// write-only: read as one, written as the other).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shares_address_with: Option<String>,
    /// Shows the live value, but keeps its value while the drive is tripped.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub live_except_while_tripped: bool,
    /// Its scale chosen by another register.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scale_by: Option<ScaleByIr>,
    /// Its copies on each port (port id, register code), when it exists once per port.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub per_port: Vec<(String, String)>,
    /// Values it takes besides its range, each with its raw word.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub special_values: Vec<SpecialValueIr>,
}

/// A value a register takes besides its range.
#[derive(Debug, Clone, Serialize)]
pub struct SpecialValueIr {
    /// The value as the manual writes it.
    pub value: f64,
    /// Its raw word.
    pub raw: u32,
    /// Identifier.
    pub id: String,
    /// English meaning.
    pub name: String,
    /// Chinese meaning.
    pub name_zh: String,
}

impl RegisterIr {
    /// The register as one of its scale choices makes it (`scale_by`): that choice's scale
    /// and raw range, the same bounding registers, and no default (the default is given in
    /// the register's own scale).
    pub fn with_scale_choice(&self, choice: &ScaleChoiceIr) -> RegisterIr {
        let mut chosen = self.clone();
        chosen.scale = choice.scale;
        chosen.scale_by = None;
        chosen.default = None;
        chosen.min = Some(BoundIr {
            raw: choice.raw_min,
            register: self.min.as_ref().and_then(|b| b.register.clone()),
        });
        chosen.max = Some(BoundIr {
            raw: choice.raw_max,
            register: self.max.as_ref().and_then(|b| b.register.clone()),
        });
        chosen
    }

    /// Whether the register may be written (text is read only, whatever `access` says).
    pub fn writable(&self) -> bool {
        self.access != Access::ReadOnly && self.data_type != DataType::Text
    }

    /// Whether the register may be written persistently (EEPROM).
    pub fn persistable(&self) -> bool {
        self.writable() && !self.ram_only
    }

    /// The lowest and highest raw values the word accepts without a range.
    pub fn raw_limits(&self) -> (i64, i64) {
        self.data_type.raw_limits(self.signed)
    }

    /// The factory value as the raw word on the wire (two's complement for signed
    /// values), when the description gives a default.
    pub fn default_raw(&self) -> Option<u32> {
        let default = self.default?;
        if let Some(special) = self.special_values.iter().find(|s| s.value == default) {
            return Some(special.raw);
        }
        let raw = (default / self.scale).round() as i64;
        let bits = u32::from(self.data_type.size().max(1)) * 8;
        let mask = if bits >= 32 {
            u32::MAX
        } else {
            (1u32 << bits) - 1
        };
        Some((raw as u32) & mask)
    }

    /// Static raw bounds: the range's, else the word's.
    pub fn raw_range(&self) -> (i64, i64) {
        let (low, high) = self.raw_limits();
        (
            self.min.as_ref().map_or(low, |b| b.raw),
            self.max.as_ref().map_or(high, |b| b.raw),
        )
    }
}

/// A worked value example (`80 Hz = 1F40h`).
#[derive(Debug, Clone, Serialize)]
pub struct ValueExampleIr {
    /// Id of the register.
    pub register: String,
    /// Engineering value.
    pub value: f64,
    /// Raw word.
    pub raw: u32,
    /// Manual section.
    pub source: String,
    /// The manual's words.
    pub description: String,
    /// Values of other registers the example assumes: (code, value).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub given: Vec<(String, u32)>,
}

/// Mode-dependent reference scaling.
#[derive(Debug, Clone, Serialize)]
pub struct ReferenceScalingIr {
    /// Manual section.
    pub source: String,
    /// Raw value meaning 100 %.
    pub full_scale_raw: u32,
    /// Ids of the registers it applies to.
    pub applies_to: Vec<String>,
    /// Id of the register choosing the mode.
    pub selector: String,
    /// Remarks.
    pub note: String,
    /// The modes.
    pub modes: Vec<ScalingModeIr>,
}

/// One mode of a reference scaling.
#[derive(Debug, Clone, Serialize)]
pub struct ScalingModeIr {
    /// Selector value.
    pub selector: u32,
    /// Low end of the span.
    pub low: SpanEndIr,
    /// High end of the span.
    pub high: SpanEndIr,
    /// The manual's wording of the rule.
    pub description: String,
}

/// One end of a span: a number, or another register's value (by id).
#[derive(Debug, Clone, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SpanEndIr {
    /// A constant.
    Number(f64),
    /// The engineering value of a register, by id.
    Register(String),
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

/// One example exchange from the manual.
#[derive(Debug, Clone, Serialize)]
pub struct ExampleIr {
    /// Identifier.
    pub id: String,
    /// Id of the protocol (within the drive).
    pub protocol: String,
    /// Manual section.
    pub source: String,
    /// The manual's words.
    pub description: String,
    /// The manual's Chinese words.
    pub description_zh: String,
    /// The request, when the example has one.
    pub request: Option<FrameIr>,
    /// The reply, when the example has one.
    pub reply: Option<FrameIr>,
    /// The data's value in the register's unit.
    pub value: Option<f64>,
    /// Id of the described register the example's data belongs to, if any.
    pub register: Option<String>,
    /// The example has both frames, and its reply answers its request.
    pub answers: bool,
    /// The manual says nothing comes back to the request (`no_reply: true`).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub no_reply: bool,
    /// A request the drive does not answer (the decoder refuses it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ignored_request: Option<UnansweredIr>,
    /// The drive settings the frames assume: (register code, value in its unit).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub settings: Vec<(String, f64)>,
    /// Why the virtual drive cannot give the example's reply, when it cannot.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_simulated: Option<String>,
    /// The protocol variant the frames are in (`None`: the first).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub variant: Option<String>,
    /// The page the drive is on for the frames, on a protocol with pages.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub page: Option<u16>,
}

/// A multi-step example: one call of the master and every frame it puts on the line.
#[derive(Debug, Clone, Serialize)]
pub struct SequenceIr {
    /// Identifier.
    pub id: String,
    /// Id of the protocol (within the drive).
    pub protocol: String,
    /// Manual section.
    pub source: String,
    /// The manual's words.
    pub description: String,
    /// The manual's Chinese words.
    pub description_zh: String,
    /// The station addressed.
    pub address: Option<u8>,
    /// Id of the register the call reads or writes.
    pub register: String,
    /// What the call does.
    pub call: SequenceCallIr,
    /// The write goes to RAM and EEPROM.
    pub persistent: bool,
    /// The persistence selector's value the master is told first.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub selector_given: Option<u32>,
    /// What it returns.
    pub result: SequenceResultIr,
    /// The frames, in order.
    pub steps: Vec<SequenceStepIr>,
    /// The protocol variant the frames are in (`None`: the first).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub variant: Option<String>,
    /// The reply-wait field's value in the master's requests (0 when left out).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reply_wait: Option<u8>,
}

/// The call of a sequence.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SequenceCallIr {
    /// A typed read.
    Read,
    /// A typed write of this value (RAM).
    Write(f64),
    /// A write of this raw word, sent as given.
    WriteRaw(u32),
}

/// The result of a sequence's call.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SequenceResultIr {
    /// This value read.
    Value(f64),
    /// The write succeeded.
    Written,
    /// The drive refused with this code (its id).
    Error(u16, String),
}

/// One frame of a sequence.
#[derive(Debug, Clone, Serialize)]
pub struct SequenceStepIr {
    /// Who sends it.
    pub from: crate::parse::model::Sender,
    /// The bytes.
    pub bytes: Vec<u8>,
    /// How the manual shows it.
    pub shown: crate::parse::model::Shown,
    /// What it is, for people.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub note: String,
}

/// One frame of an example.
#[derive(Debug, Clone, Serialize)]
pub struct FrameIr {
    /// The bytes.
    pub bytes: Vec<u8>,
    /// Written as text in the description (`ascii:`).
    pub text: bool,
    /// What the bytes mean, as the runtime's decoder reads them.
    pub meaning: FrameMeaning,
    /// The manual's misprint, when there is an erratum.
    pub printed: Option<PrintedIr>,
}

/// A request the manual prints as one the drive does not answer.
#[derive(Debug, Clone, Serialize)]
pub struct UnansweredIr {
    /// The bytes.
    pub bytes: Vec<u8>,
    /// The decoder's reason for refusing them.
    pub rejected_as: DecodeErrorKind,
    /// The decoder's message.
    pub rejection: String,
    /// Why the drive does not answer, as the manual says.
    pub reason: String,
}

/// Bytes a manual printed wrong.
#[derive(Debug, Clone, Serialize)]
pub struct PrintedIr {
    /// The printed bytes.
    pub bytes: Vec<u8>,
    /// Why they are wrong.
    pub erratum: String,
    /// The decoder's reason for rejecting them, or why they are wrong in their exchange.
    pub rejected_as: PrintedRejection,
    /// The decoder's message.
    pub rejection: String,
    /// The printed bytes as the description writes them (`2F 52 00 10 0064 FA`, the
    /// manual's spacing), for the page; not part of the snapshot.
    #[serde(skip)]
    pub written: String,
}
