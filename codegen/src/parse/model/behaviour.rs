//! The behaviour model of a drive (`behaviour:`), for the virtual drive: command bits and
//! codes, the frequency ramp, current, status bits, trips, process words and refusals.

use super::defaults::one;
use super::range::BoundModel;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

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
