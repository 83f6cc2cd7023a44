//! The control roles of a drive, found in its description's behaviour model (the same one
//! its virtual drive runs): the command register and how it runs, reverses, stops, coasts
//! and resets the motor; the speed command and the command-word bits it needs to act; the
//! monitors of the output frequency, the set point and the output current; the status
//! bits or state codes; the present trip code; the operation mode commands need. Found
//! once per drive, by register id; nothing here names a drive.

use vfd_runtime::behaviour::{
    Amount, Bit, CommandCodes, ModeRequirement, StatusState, WrittenValue,
};
use vfd_runtime::{DriveInfo, RegisterInfo};

/// How the command register makes the motor act.
#[derive(Debug, Clone, Copy)]
pub enum Command {
    /// Bits of a command word (and bits held by other registers or coils).
    Bits(CommandBits),
    /// A code written for each action (run forward, run reverse, stop, coast, reset).
    Codes(CommandCodes),
}

/// The bits of a command word, by what they do.
#[derive(Debug, Clone, Copy)]
pub struct CommandBits {
    /// Bits that must act for the word to act at all.
    pub require: &'static [Bit],
    /// Run; the forward run bit where a second bit runs in reverse.
    pub run: Bit,
    /// A second run bit that runs the motor in reverse.
    pub run_reverse: Option<Bit>,
    /// The direction bit (acting: reverse).
    pub reverse: Option<Bit>,
    /// Fault reset, on its rising edge.
    pub reset: Option<Bit>,
    /// Coast stop.
    pub coast: Option<Bit>,
}

/// A drive's control roles.
#[derive(Debug, Clone, Copy)]
pub struct Roles {
    /// The drive.
    pub drive: &'static DriveInfo,
    /// The command register.
    pub command: &'static RegisterInfo,
    /// How it acts.
    pub kind: Command,
    /// The speed (frequency) command.
    pub speed: &'static RegisterInfo,
    /// Command-word bits the speed command needs to act.
    pub speed_require: &'static [Bit],
    /// What the speed command's 100 % stands for, where it is a percentage of a frequency
    /// (the output and set point monitors then read in that frequency's unit).
    pub percent_of: Option<Amount>,
    /// The monitor of the output frequency (in the speed command's units).
    pub output: Option<&'static RegisterInfo>,
    /// The monitor of the set point in use (the speed command itself where none is).
    pub set_point: &'static RegisterInfo,
    /// The monitor of the output current.
    pub current: Option<&'static RegisterInfo>,
    /// The status words, with their bits.
    pub status: &'static [&'static str],
    /// The register showing the state as a code.
    pub state: Option<StatusState>,
    /// Status bits acting while running.
    pub running: &'static [Bit],
    /// Status bits acting while reversed.
    pub reverse: &'static [Bit],
    /// Status bits acting while running forward.
    pub forward: &'static [Bit],
    /// Status bits acting at the set point.
    pub at_speed: &'static [Bit],
    /// Status bits acting while tripped.
    pub tripped: &'static [Bit],
    /// The register showing the present trip code.
    pub trip_code: Option<&'static RegisterInfo>,
    /// A fault reset by a value written to a register of its own.
    pub reset_by_write: Option<WrittenValue>,
    /// The operation mode the drive must be in to take commands over the link.
    pub mode: Option<ModeRequirement>,
}

/// The roles a drive lacks for control, by name.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MissingRoles {
    /// The drive's id.
    pub drive: &'static str,
    /// The roles not found (`command`, `speed`, `state`, ...).
    pub missing: Vec<&'static str>,
}

impl std::fmt::Display for MissingRoles {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "drive {} cannot be controlled: its description has no {} role{} (its `behaviour:` section names them)",
            self.drive,
            self.missing.join(", "),
            if self.missing.len() == 1 { "" } else { "s" }
        )
    }
}

impl std::error::Error for MissingRoles {}

impl Roles {
    /// The roles of `drive`, or the ones it lacks: a command register, a speed command,
    /// and a way to tell whether the motor runs (status bits or a state register).
    pub fn of(drive: &'static DriveInfo) -> Result<Roles, MissingRoles> {
        let lacking = |missing: Vec<&'static str>| MissingRoles {
            drive: drive.id,
            missing,
        };
        let Some(behaviour) = drive.behaviour else {
            return Err(lacking(vec!["command", "speed", "state"]));
        };
        let command = drive.register(behaviour.command.register);
        let speed = drive.register(behaviour.frequency.command);
        let status = &behaviour.status;
        let has_state = status.state.is_some() || !status.running.is_empty();
        let mut missing = Vec::new();
        if command.is_none() {
            missing.push("command");
        }
        if speed.is_none() {
            missing.push("speed");
        }
        if !has_state {
            missing.push("state");
        }
        let (Some(command), Some(speed), true) = (command, speed, has_state) else {
            return Err(lacking(missing));
        };
        let c = &behaviour.command;
        let kind = match c.codes {
            Some(codes) => Command::Codes(codes),
            None => Command::Bits(CommandBits {
                require: c.require,
                run: c.run,
                run_reverse: c.run_reverse,
                reverse: c.reverse,
                reset: c.reset,
                coast: c.coast,
            }),
        };
        let first = |ids: &[&str]| ids.iter().find_map(|id| drive.register(id));
        Ok(Roles {
            drive,
            command,
            kind,
            speed,
            speed_require: behaviour.frequency.require,
            percent_of: behaviour.frequency.percent_of,
            output: first(behaviour.frequency.output),
            set_point: first(behaviour.frequency.reference).unwrap_or(speed),
            current: behaviour.current.as_ref().and_then(|c| first(c.registers)),
            status: status.registers,
            state: status.state,
            running: status.running,
            reverse: status.reverse,
            forward: status.forward,
            at_speed: status.at_reference,
            tripped: status.tripped,
            trip_code: first(behaviour.trip.code),
            reset_by_write: c.reset_by_write,
            mode: c.require_mode,
        })
    }

    /// Whether the drive can coast to a stop on command.
    pub fn can_coast(&self) -> bool {
        match self.kind {
            Command::Bits(bits) => bits.coast.is_some(),
            Command::Codes(codes) => !codes.coast.is_empty(),
        }
    }

    /// Whether the drive can reset a trip on command.
    pub fn can_reset(&self) -> bool {
        self.reset_by_write.is_some()
            || match self.kind {
                Command::Bits(bits) => bits.reset.is_some(),
                Command::Codes(codes) => !codes.reset.is_empty(),
            }
    }

    /// Whether the drive can run in reverse on command.
    pub fn can_reverse(&self) -> bool {
        match self.kind {
            Command::Bits(bits) => bits.reverse.is_some() || bits.run_reverse.is_some(),
            Command::Codes(codes) => !codes.run_reverse.is_empty(),
        }
    }

    /// Whether the drive shows a trip: status bits, a state code or a trip code.
    pub fn shows_trips(&self) -> bool {
        !self.tripped.is_empty() || self.state.is_some() || self.trip_code.is_some()
    }

    /// The roles present, by name, for `vfd check` and `vfd info`.
    pub fn names(&self) -> Vec<&'static str> {
        let mut names = vec!["run", "stop", "speed", "state"];
        if self.can_reverse() {
            names.push("reverse");
        }
        if self.can_coast() {
            names.push("coast");
        }
        if self.can_reset() {
            names.push("reset");
        }
        if self.output.is_some() {
            names.push("output frequency");
        }
        if self.current.is_some() {
            names.push("output current");
        }
        if self.shows_trips() {
            names.push("tripped");
        }
        if self.trip_code.is_some() {
            names.push("trip code");
        }
        names
    }
}
