//! What the virtual drive does with one request ([`Outcome`]: a reply, or silence) and why
//! it refuses one ([`Refusal`], each mapped to the manual's error code by the behaviour
//! model's refusals).

use crate::behaviour::Refusals;

/// Why the virtual drive refused a request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    /// No register at that number (or index).
    UnknownRegister,
    /// A write to a read-only register (or a persistent write of a RAM-only one).
    ReadOnly,
    /// A value outside the register's range, bounds named after other registers included.
    OutOfRange,
    /// A write to a register that cannot change while the motor runs.
    WhileRunning,
    /// A frame whose checksum does not match.
    BadChecksum,
    /// A write to the command word or the frequency command while the mode register is
    /// outside the mode the behaviour model requires.
    WrongMode,
    /// A frame holding a character no frame of the protocol carries.
    BadCharacter,
    /// A frame that cannot be read otherwise.
    Malformed,
}

impl Refusal {
    /// The error code `refusals` gives for it; `None`: the drive stays silent.
    pub fn code(self, refusals: &Refusals) -> Option<u16> {
        match self {
            Refusal::UnknownRegister => refusals.unknown_register,
            Refusal::ReadOnly => refusals.read_only,
            Refusal::OutOfRange => refusals.out_of_range,
            Refusal::WhileRunning => refusals.while_running,
            Refusal::BadChecksum => refusals.bad_checksum,
            Refusal::WrongMode => refusals.wrong_mode,
            Refusal::BadCharacter => refusals.bad_character,
            Refusal::Malformed => refusals.malformed,
        }
    }
}

/// What the drive does with one request frame.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Outcome {
    /// It answers with these bytes.
    Reply(Vec<u8>),
    /// It stays silent, for this reason.
    Silent(&'static str),
}
