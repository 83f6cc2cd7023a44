//! The behaviour model for the virtual drive, resolved to register ids and bit masks.

use serde::Serialize;

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
