//! What each control operation writes, in order, prepared without a line (sans I/O): the
//! command word with the bits an action needs (and the bits it needs held, such as a
//! "command enabled" or "data valid" bit, and active-low bits left inactive), bits held by
//! other registers or coils set one by one before the word, or the code a command register
//! takes for the action.

use super::roles::{Command, CommandBits, Roles};
use vfd_runtime::behaviour::Bit;
use vfd_runtime::RegisterInfo;

/// A direction of rotation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Direction {
    /// Forward.
    Forward,
    /// Reverse.
    Reverse,
}

/// An action of the command register.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// Run in a direction.
    Run(Direction),
    /// Stop, ramping down.
    Stop,
    /// Coast to a stop.
    Coast,
    /// Reset a trip (the edge: see [`Step::Pulse`]).
    Reset,
}

/// One write of an operation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Step {
    /// Write `raw` to `register`.
    Write {
        /// The register.
        register: &'static RegisterInfo,
        /// The raw value.
        raw: u32,
    },
    /// Set one bit of `register` (a field of another bit-field register, or a coil),
    /// keeping its other bits as the drive holds them.
    Bit {
        /// The register holding the bit.
        register: &'static RegisterInfo,
        /// The bit.
        bit: Bit,
        /// Acting or not.
        on: bool,
    },
    /// Write `raw` to `register`, then `after`: a rising edge (a reset bit set, then
    /// cleared so the next reset has an edge again).
    Pulse {
        /// The register.
        register: &'static RegisterInfo,
        /// The value with the bit acting.
        raw: u32,
        /// The value after.
        after: u32,
    },
}

/// The steps of `action` on a drive with `roles`, or `None` where the drive cannot do it
/// (no coast, no reset, no reverse).
pub fn steps(roles: &Roles, action: Action) -> Option<Vec<Step>> {
    let command = roles.command;
    match roles.kind {
        Command::Codes(codes) => {
            let list = match action {
                Action::Run(Direction::Forward) => codes.run,
                Action::Run(Direction::Reverse) => codes.run_reverse,
                Action::Stop => codes.stop,
                Action::Coast => codes.coast,
                Action::Reset => codes.reset,
            };
            match (list.first(), action, roles.reset_by_write) {
                (Some(&raw), _, _) => Some(vec![Step::Write {
                    register: command,
                    raw,
                }]),
                (None, Action::Reset, Some(written)) => reset_by_write(roles, written),
                (None, Action::Stop, _) => codes.coast.first().map(|&raw| {
                    vec![Step::Write {
                        register: command,
                        raw,
                    }]
                }),
                (None, _, _) => None,
            }
        }
        Command::Bits(bits) => bit_steps(roles, bits, action),
    }
}

fn reset_by_write(
    roles: &Roles,
    written: vfd_runtime::behaviour::WrittenValue,
) -> Option<Vec<Step>> {
    let register = roles.drive.register(written.register)?;
    Some(vec![Step::Write {
        register,
        raw: written.value,
    }])
}

/// Whether `bit` is held by a register other than the command register (a bit naming the
/// command register itself, as a coil's own bit does, is in the word).
fn held_elsewhere(roles: &Roles, bit: Bit) -> bool {
    bit.register.is_some_and(|id| {
        !roles
            .drive
            .register(id)
            .is_some_and(|r| std::ptr::eq(r, roles.command))
    })
}

/// The word every action starts from: the bits the word needs to act, the bits the speed
/// command needs, active-low bits inactive (a coast bit that stops while 0 is 1).
fn base_word(roles: &Roles, bits: &CommandBits) -> u32 {
    let mut word = 0;
    for bit in bits.require.iter().chain(roles.speed_require) {
        if !held_elsewhere(roles, *bit) {
            word = bit.apply(word, true);
        }
    }
    for bit in [bits.coast, bits.reset, bits.reverse, bits.run_reverse]
        .into_iter()
        .flatten()
        .chain([bits.run])
    {
        if !held_elsewhere(roles, bit) {
            word = bit.apply(word, false);
        }
    }
    word
}

fn bit_steps(roles: &Roles, bits: CommandBits, action: Action) -> Option<Vec<Step>> {
    let command = roles.command;
    let base = base_word(roles, &bits);
    let mut before = Vec::new();
    // Bits the word needs that another register holds are set first.
    for bit in bits.require.iter().chain(roles.speed_require) {
        if held_elsewhere(roles, *bit) {
            before.extend(elsewhere(roles, *bit, true));
        }
    }
    let in_word = |word: u32, bit: Bit, on: bool, before: &mut Vec<Step>| {
        if held_elsewhere(roles, bit) {
            before.extend(elsewhere(roles, bit, on));
            word
        } else {
            bit.apply(word, on)
        }
    };
    let word = match action {
        Action::Run(direction) => {
            let reverse = direction == Direction::Reverse;
            match (reverse, bits.run_reverse, bits.reverse) {
                (true, Some(run_reverse), _) => {
                    let word = in_word(base, bits.run, false, &mut before);
                    in_word(word, run_reverse, true, &mut before)
                }
                (_, _, Some(reverse_bit)) => {
                    let word = in_word(base, reverse_bit, reverse, &mut before);
                    in_word(word, bits.run, true, &mut before)
                }
                (true, None, None) => return None,
                (false, _, None) => in_word(base, bits.run, true, &mut before),
            }
        }
        Action::Stop => in_word(base, bits.run, false, &mut before),
        Action::Coast => {
            let coast = bits.coast?;
            in_word(base, coast, true, &mut before)
        }
        Action::Reset => match (bits.reset, roles.reset_by_write) {
            (Some(reset), _) if !held_elsewhere(roles, reset) => {
                before.push(Step::Pulse {
                    register: command,
                    raw: reset.apply(base, true),
                    after: base,
                });
                return Some(before);
            }
            (Some(reset), _) => {
                let register = roles.drive.register(reset.register?)?;
                before.push(Step::Bit {
                    register,
                    bit: reset,
                    on: true,
                });
                before.push(Step::Bit {
                    register,
                    bit: reset,
                    on: false,
                });
                return Some(before);
            }
            (None, Some(written)) => return reset_by_write(roles, written),
            (None, None) => return None,
        },
    };
    before.push(Step::Write {
        register: command,
        raw: word,
    });
    Some(before)
}

/// The step setting `bit`, held by a register other than the command word, to `on`.
fn elsewhere(roles: &Roles, bit: Bit, on: bool) -> Option<Step> {
    let register = roles.drive.register(bit.register?)?;
    Some(Step::Bit { register, bit, on })
}
