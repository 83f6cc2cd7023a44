//! The behaviour model a drive description declares (its `behaviour:` section), as static
//! data for the virtual drive: which command-word bits start, stop, reverse, reset and
//! coast the simulated motor, which register is the frequency command, which monitors
//! follow the output, which status bits show the drive's state, where trips are recorded
//! and which error code each protocol answers a refused request with.
//!
//! Registers are named by their description id; bits are resolved to masks by the code
//! generator. Nothing here names a drive.

/// One bit of a word, resolved from a bit-field id: its mask, whether it acts when 0, and
/// the register holding it when that is not the command (or status) word.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Bit {
    /// The bit's mask in the word.
    pub mask: u32,
    /// The bit acts when it is 0 (FC "coast stop" is active low).
    pub active_low: bool,
    /// Id of the register holding the bit, when it is not the word its role belongs to:
    /// a field of another bit-field register (the GS2's direction command P9.28 beside its
    /// run command P9.27), or a coil of its own (mask FF00h: the coil is on).
    pub register: Option<&'static str>,
}

impl Bit {
    /// An active-high bit with this mask.
    pub const fn high(mask: u32) -> Bit {
        Bit {
            mask,
            active_low: false,
            register: None,
        }
    }

    /// An active-low bit with this mask.
    pub const fn low(mask: u32) -> Bit {
        Bit {
            mask,
            active_low: true,
            register: None,
        }
    }

    /// The same bit, held by the register with this id instead of the role's word.
    pub const fn in_register(self, register: &'static str) -> Bit {
        Bit {
            register: Some(register),
            ..self
        }
    }

    /// A bit no word sets: the run bit of a model whose command register holds codes
    /// ([`CommandBehaviour::codes`]).
    pub const NONE: Bit = Bit::high(0);

    /// Whether the bit acts in `word`.
    pub const fn is_active(self, word: u32) -> bool {
        (word & self.mask != 0) != self.active_low
    }

    /// `word` with the bit set to act (`on`) or not.
    pub const fn apply(self, word: u32, on: bool) -> u32 {
        if on != self.active_low {
            word | self.mask
        } else {
            word & !self.mask
        }
    }
}

/// A quantity the model needs: a fixed number, or the current value of a register (by id),
/// in that register's engineering units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Amount {
    /// A fixed number.
    Value(f64),
    /// The value of the register with this id.
    Register(&'static str),
}

/// A value written to a register (by id) that makes the drive act: the DV1 resets when
/// 9696h is written to 1101h.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WrittenValue {
    /// Id of the register written.
    pub register: &'static str,
    /// The raw value that acts.
    pub value: u32,
}

/// A register whose value must be one of `values` for the drive to take commands over the
/// link (the DV1's operation mode 1000h = 0, communication mode).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ModeRequirement {
    /// Id of the mode register.
    pub register: &'static str,
    /// The raw values in which commands are taken.
    pub values: &'static [u32],
}

/// How the command word drives the simulated motor.
#[derive(Debug, Clone, PartialEq)]
pub struct CommandBehaviour {
    /// Id of the command-word register.
    pub register: &'static str,
    /// Bits that must all act for the word to act at all (YD1000 bit 15, FC "data valid").
    pub require: &'static [Bit],
    /// Run (1) or stop (0); with `run_reverse`, the forward run bit. [`Bit::NONE`] when the
    /// register holds codes ([`CommandBehaviour::codes`]).
    pub run: Bit,
    /// A second run bit that runs the motor in reverse (the DV1's STR beside STF): the
    /// motor runs while either acts, in reverse when only this one does, and stops while
    /// both act.
    pub run_reverse: Option<Bit>,
    /// Reverse direction.
    pub reverse: Option<Bit>,
    /// Fault reset, on the rising edge.
    pub reset: Option<Bit>,
    /// Fault reset by a value written to a register of its own (not a command-word bit).
    pub reset_by_write: Option<WrittenValue>,
    /// Coast stop: the output drops to zero at once.
    pub coast: Option<Bit>,
    /// The mode in which the command word and the frequency command are taken: writes to
    /// either in another mode are refused ([`Refusals::wrong_mode`]).
    pub require_mode: Option<ModeRequirement>,
    /// The register holds a command code, not bits (the Powtran PI500's 2000H: 1 runs
    /// forward, 6 stops): what each value written does. The bits above are then unused.
    pub codes: Option<CommandCodes>,
}

impl CommandBehaviour {
    /// The command word that runs the motor forward, from `word` (the other bits as they
    /// are): the run bit set, or the first run code of a register that holds codes.
    pub fn run_word(&self, word: u32) -> u32 {
        match self.codes {
            Some(codes) => codes.run.first().copied().unwrap_or(word),
            None => self.run.apply(word, true),
        }
    }

    /// The command word that stops the motor, from `word`: the run bit cleared, or the
    /// first stop (else coast) code of a register that holds codes.
    pub fn stop_word(&self, word: u32) -> u32 {
        match self.codes {
            Some(codes) => codes
                .stop
                .first()
                .or(codes.coast.first())
                .copied()
                .unwrap_or(word),
            None => self.run.apply(word, false),
        }
    }
}

/// The raw values of a command register that holds codes, by what each does when written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CommandCodes {
    /// Run forward.
    pub run: &'static [u32],
    /// Run in reverse.
    pub run_reverse: &'static [u32],
    /// Stop: the output ramps down.
    pub stop: &'static [u32],
    /// Coast to a stop: the output drops to zero at once.
    pub coast: &'static [u32],
    /// Reset a trip (each write acts; the motor stays stopped).
    pub reset: &'static [u32],
}

/// A register showing the drive's state as a code rather than bits (the PI500's 3000H:
/// 1 forward running, 2 reverse running, 3 stopped, 4 tripped).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StatusState {
    /// Id of the register.
    pub register: &'static str,
    /// Its value while stopped and not tripped.
    pub stopped: u32,
    /// Its value while the motor runs forward.
    pub forward: u32,
    /// Its value while the motor runs in reverse.
    pub reverse: u32,
    /// Its value while tripped.
    pub tripped: u32,
}

impl StatusState {
    /// Whether the register's value `raw` says the motor runs.
    pub const fn shows_running(self, raw: u32) -> bool {
        raw == self.forward || raw == self.reverse
    }
}

/// How the output frequency follows the frequency command.
#[derive(Debug, Clone, PartialEq)]
pub struct FrequencyBehaviour {
    /// Id of the frequency-command register.
    pub command: &'static str,
    /// Command-word bits that make the frequency command effective.
    pub require: &'static [Bit],
    /// Time the output takes to rise by `span`, in seconds.
    pub acceleration: Amount,
    /// Time the output takes to fall by `span`, in seconds.
    pub deceleration: Amount,
    /// The change the ramp times refer to, in the frequency command's units.
    pub span: Amount,
    /// Ids of the monitors that show the output (same units as the command).
    pub output: &'static [&'static str],
    /// Ids of the monitors that show the frequency command in use.
    pub reference: &'static [&'static str],
    /// The output frequency at and above which the drive reports the frequency detected
    /// ([`StatusBehaviour::frequency_detected`]), in the command's units.
    pub detection: Option<Amount>,
    /// Where the command is a percentage: the frequency its 100 % stands for (a maximum
    /// frequency). The output then runs at command x `percent_of` / 100, and `span`,
    /// `detection` and the monitors are in `percent_of`'s units.
    pub percent_of: Option<Amount>,
}

/// Output current as a simple function of the output: `at_zero + (at_span - at_zero) x
/// |output| / span` while running, 0 when stopped.
#[derive(Debug, Clone, PartialEq)]
pub struct CurrentBehaviour {
    /// Ids of the monitors that show it.
    pub registers: &'static [&'static str],
    /// Value at zero output while running.
    pub at_zero: f64,
    /// Value at an output of `span`.
    pub at_span: f64,
    /// The current at and above which the drive reports an overload
    /// ([`StatusBehaviour::overload`]), in the monitors' units.
    pub overload: Option<Amount>,
}

/// Which status bits show the drive's state. Each entry lists the bits set while it holds.
#[derive(Debug, Clone, PartialEq)]
pub struct StatusBehaviour {
    /// Ids of the status-word registers.
    pub registers: &'static [&'static str],
    /// Set while the motor runs (run commanded or output not zero).
    pub running: &'static [Bit],
    /// Set while the direction is reverse.
    pub reverse: &'static [Bit],
    /// Set while the motor runs in the forward direction.
    pub forward: &'static [Bit],
    /// Set while running with the output at the frequency command.
    pub at_reference: &'static [Bit],
    /// Set while tripped.
    pub tripped: &'static [Bit],
    /// Set while the output current is at or above [`CurrentBehaviour::overload`].
    pub overload: &'static [Bit],
    /// Set while running with the output frequency at or above
    /// [`FrequencyBehaviour::detection`].
    pub frequency_detected: &'static [Bit],
    /// Set unless a coast stop is commanded.
    pub enabled: &'static [Bit],
    /// Always set (ready bits).
    pub always: &'static [Bit],
    /// A register showing the state as a code, beside (or instead of) the status words.
    pub state: Option<StatusState>,
}

/// One place of a trip history: a whole register, or a field of a bit-field register (the
/// DV1 keeps two fault codes per word, one per byte).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TripSlot {
    /// Id of the register.
    pub register: &'static str,
    /// The bits of the register the slot holds (`u32::MAX`: all of them).
    pub mask: u32,
}

impl TripSlot {
    /// A slot that is a whole register.
    pub const fn whole(register: &'static str) -> TripSlot {
        TripSlot {
            register,
            mask: u32::MAX,
        }
    }

    /// The slot's value in the register's `word`.
    pub const fn get(self, word: u32) -> u32 {
        (word & self.mask) >> self.mask.trailing_zeros()
    }

    /// `word` with the slot set to `value` (cut to the slot's width).
    pub const fn put(self, word: u32, value: u32) -> u32 {
        let shifted = match value.checked_shl(self.mask.trailing_zeros()) {
            Some(shifted) => shifted,
            None => 0,
        };
        (word & !self.mask) | (shifted & self.mask)
    }
}

/// Where a trip is recorded.
#[derive(Debug, Clone, PartialEq)]
pub struct TripBehaviour {
    /// Ids of the registers showing the present trip code (0 after a reset).
    pub code: &'static [&'static str],
    /// The trip history, newest first: a trip shifts every slot one place older.
    pub history: &'static [TripSlot],
    /// A value written to a register that clears the trip history (the DV1's 1102h =
    /// A5A5h).
    pub clear_by_write: Option<WrittenValue>,
}

/// Which registers the process words of a process exchange carry.
#[derive(Debug, Clone, PartialEq)]
pub struct ProcessBehaviour {
    /// Id of the register the first request word is written to (control word).
    pub control: &'static str,
    /// Id of the register the second request word is written to (reference).
    pub reference: &'static str,
    /// Id of the register the first reply word reads (status word).
    pub status: &'static str,
    /// Id of the register the second reply word reads (output).
    pub output: &'static str,
}

/// The error code one protocol answers each kind of refused request with; `None`: the
/// drive stays silent.
#[derive(Debug, Clone, PartialEq)]
pub struct Refusals {
    /// Protocol id (within the drive).
    pub protocol: &'static str,
    /// No register at that number.
    pub unknown_register: Option<u16>,
    /// Write to a read-only register.
    pub read_only: Option<u16>,
    /// Value outside the range, including bounds named after other registers.
    pub out_of_range: Option<u16>,
    /// Write to a register that cannot change while the motor runs.
    pub while_running: Option<u16>,
    /// A frame whose checksum does not match.
    pub bad_checksum: Option<u16>,
    /// A write to the command word or the frequency command outside the mode the model
    /// requires ([`CommandBehaviour::require_mode`]).
    pub wrong_mode: Option<u16>,
    /// A frame holding a character no frame of the protocol carries (a character error).
    pub bad_character: Option<u16>,
    /// A frame that cannot be read otherwise, whose station can be (a protocol error).
    pub malformed: Option<u16>,
    /// The code answering an unreadable frame once more than `after` came in a row (bad
    /// characters, malformed frames, bad checksums): the computer link's NAK error.
    pub retries_exceeded: Option<RetriesExceeded>,
}

/// The error a drive answers once too many unreadable frames came in a row
/// ([`Refusals::retries_exceeded`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RetriesExceeded {
    /// The error code.
    pub code: u16,
    /// How many unreadable frames in a row get their own errors (a number, or the register
    /// setting the allowed retries); the next gets `code`.
    pub after: Amount,
}

impl Refusals {
    /// Silent for every refusal.
    pub const SILENT: Refusals = Refusals {
        protocol: "",
        unknown_register: None,
        read_only: None,
        out_of_range: None,
        while_running: None,
        bad_checksum: None,
        wrong_mode: None,
        bad_character: None,
        malformed: None,
        retries_exceeded: None,
    };
}

/// A drive's behaviour model, as its description declares it.
#[derive(Debug, Clone, PartialEq)]
pub struct Behaviour {
    /// The manual sections it comes from.
    pub source: &'static str,
    /// The command word.
    pub command: CommandBehaviour,
    /// The frequency command and the output.
    pub frequency: FrequencyBehaviour,
    /// The output current, if modelled.
    pub current: Option<CurrentBehaviour>,
    /// The status bits.
    pub status: StatusBehaviour,
    /// Trip records.
    pub trip: TripBehaviour,
    /// Process words, for protocols that carry them.
    pub process: Option<ProcessBehaviour>,
    /// Error codes per protocol.
    pub refusals: &'static [Refusals],
}

impl Behaviour {
    /// The refusal codes of the protocol with this id (silent when it has none).
    pub fn refusals(&self, protocol: &str) -> &Refusals {
        self.refusals
            .iter()
            .find(|r| r.protocol == protocol)
            .unwrap_or(&Refusals::SILENT)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_act_high_or_low() {
        let run = Bit::high(0x0400);
        assert!(run.is_active(0x0400) && !run.is_active(0));
        assert_eq!(run.apply(0, true), 0x0400);
        let coast = Bit::low(0x0008);
        assert!(coast.is_active(0) && !coast.is_active(0x0008));
        assert_eq!(coast.apply(0, false), 0x0008);
        assert_eq!(coast.apply(0x0008, true), 0);
    }

    #[test]
    fn trip_slots_are_whole_words_or_fields() {
        let whole = TripSlot::whole("a");
        assert_eq!(whole.get(0x1234), 0x1234);
        assert_eq!(whole.put(0x1234, 0x21), 0x21);
        let high = TripSlot {
            register: "a",
            mask: 0xFF00,
        };
        assert_eq!(high.get(0x2107), 0x21);
        assert_eq!(high.put(0x2107, 0x1FF), 0xFF07, "cut to the slot's width");
    }

    #[test]
    fn unknown_protocols_are_silent() {
        let behaviour = Behaviour {
            source: "",
            command: CommandBehaviour {
                register: "c",
                require: &[],
                run: Bit::high(1),
                run_reverse: None,
                reverse: None,
                reset: None,
                reset_by_write: None,
                coast: None,
                require_mode: None,
                codes: None,
            },
            frequency: FrequencyBehaviour {
                command: "f",
                require: &[],
                acceleration: Amount::Value(1.0),
                deceleration: Amount::Value(1.0),
                span: Amount::Value(50.0),
                output: &[],
                reference: &[],
                detection: None,
                percent_of: None,
            },
            current: None,
            status: StatusBehaviour {
                registers: &[],
                running: &[],
                forward: &[],
                reverse: &[],
                at_reference: &[],
                tripped: &[],
                overload: &[],
                frequency_detected: &[],
                enabled: &[],
                always: &[],
                state: None,
            },
            trip: TripBehaviour {
                code: &[],
                history: &[],
                clear_by_write: None,
            },
            process: None,
            refusals: &[Refusals {
                protocol: "ascii",
                out_of_range: Some(1),
                ..Refusals::SILENT
            }],
        };
        assert_eq!(behaviour.refusals("ascii").out_of_range, Some(1));
        assert_eq!(behaviour.refusals("modbus").out_of_range, None);
    }
}
