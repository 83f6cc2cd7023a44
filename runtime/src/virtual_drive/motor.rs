//! The simulated motor: the drive's behaviour model applied to its registers. Command-word
//! writes start, stop, reverse, reset and coast it; the output ramps towards the frequency
//! command on the simulated clock; monitors and status bits follow.

use super::VirtualDrive;
use crate::behaviour::{Amount, Behaviour, Bit, CommandCodes, TripSlot};
use crate::info::RegisterInfo;
use std::time::Duration;

/// State of the simulated motor.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Motor {
    /// A run command is in force.
    pub run: bool,
    /// The commanded direction is reverse.
    pub reverse: bool,
    /// A coast stop is commanded.
    pub coast: bool,
    /// The output, signed (negative: reverse), in the frequency command's units.
    pub output: f64,
    /// The trip code while tripped.
    pub trip: Option<u16>,
    /// The last command word that acted.
    pub last_word: u32,
    /// Whether the reset bit acted when the command was last taken, for reset edges.
    pub reset_active: bool,
}

/// A raw word as an engineering value.
pub(crate) fn engineering(info: &RegisterInfo, raw: u32) -> f64 {
    let value = if info.signed {
        match info.data_type.size() {
            4 => f64::from(raw as i32),
            _ => f64::from(raw as u16 as i16),
        }
    } else {
        f64::from(raw)
    };
    value * info.scale
}

/// An engineering value as a raw word, clamped to the register's static bounds.
pub(crate) fn raw_of(info: &RegisterInfo, value: f64) -> u32 {
    let raw = (value / info.scale).round() as i64;
    raw.clamp(info.raw_min, info.raw_max) as u32
}

impl VirtualDrive {
    pub(crate) fn behaviour(&self) -> Option<&'static Behaviour> {
        self.drive.behaviour
    }

    /// The engineering value of the register with this id, as the drive acts on it.
    pub(crate) fn value_of(&self, id: &str) -> Option<f64> {
        let info = self.drive.register(id)?;
        let raw = self.storage.in_effect(info, 0);
        Some(engineering(self.scaled(info), raw))
    }

    pub(super) fn amount(&self, amount: Amount) -> f64 {
        match amount {
            Amount::Value(value) => value,
            Amount::Register(id) => self.value_of(id).unwrap_or(0.0),
        }
    }

    /// Evaluates the description's conversion `id` with its register inputs as the drive
    /// holds them (values in effect) and its other inputs from `free`, in argument order.
    /// `None` when there is no such conversion, it does not apply for its selector's
    /// present value (`when`), or an input is missing.
    pub fn convert(&self, id: &str, free: &[f64]) -> Option<f64> {
        let conversion = self.drive.conversion(id)?;
        let selector = match conversion.when {
            Some((code, _)) => {
                let info = self.drive.register(code)?;
                Some(self.storage.in_effect(info, 0))
            }
            None => None,
        };
        if !conversion.applies(selector) {
            return None;
        }
        conversion.evaluate_with(|code| self.value_of(code), free)
    }

    /// Whether the motor runs: a run command in force, or an output not yet zero.
    pub fn is_running(&self) -> bool {
        (self.motor.run && !self.motor.coast && self.motor.trip.is_none())
            || self.motor.output.abs() > 1e-9
    }

    /// The output, signed (negative in reverse), in the frequency command's units.
    pub fn output(&self) -> f64 {
        self.motor.output
    }

    /// Whether `bit` acts: in `word` (the command word), or in the register holding it
    /// when it has one of its own.
    fn acts(&self, bit: Bit, word: u32) -> bool {
        match bit.register {
            Some(id) => self
                .drive
                .register(self.served(id))
                .is_some_and(|info| bit.is_active(self.storage.get(info, 0))),
            None => bit.is_active(word),
        }
    }

    fn all_act(&self, bits: &[Bit], word: u32) -> bool {
        bits.iter().all(|bit| self.acts(*bit, word))
    }

    /// The command word as the drive holds it.
    fn command_word(&self, behaviour: &Behaviour) -> u32 {
        self.drive
            .register(self.served(behaviour.command.register))
            .map_or(0, |info| self.storage.get(info, 0))
    }

    /// A command word was written (or a register holding one of its bits): it acts when
    /// its required bits are.
    pub(crate) fn command_written(&mut self, word: u32) {
        let Some(behaviour) = self.behaviour() else {
            return;
        };
        let command = &behaviour.command;
        if let Some(codes) = command.codes {
            self.command_code_written(codes, word);
            return;
        }
        if !self.all_act(command.require, word) {
            return;
        }
        let reset = command.reset.is_some_and(|bit| self.acts(bit, word));
        if reset && !self.motor.reset_active {
            self.reset();
        }
        self.motor.reset_active = reset;
        // With a reverse-run bit beside the run bit: either runs, the reverse one alone
        // in reverse, both together stop.
        let forward = self.acts(command.run, word);
        let backward = command.run_reverse.is_some_and(|bit| self.acts(bit, word));
        self.motor.run = forward != backward && self.motor.trip.is_none();
        self.motor.reverse =
            command.reverse.is_some_and(|bit| self.acts(bit, word)) || (backward && !forward);
        self.motor.coast = command.coast.is_some_and(|bit| self.acts(bit, word));
        if self.motor.coast {
            self.motor.output = 0.0;
        }
        self.motor.last_word = word;
        self.refresh();
    }

    /// A code was written to a command register that holds codes: it acts as its list
    /// says; a value in no list changes nothing.
    fn command_code_written(&mut self, codes: CommandCodes, word: u32) {
        let tripped = self.motor.trip.is_some();
        if codes.reset.contains(&word) {
            self.reset();
        } else if codes.run.contains(&word) || codes.run_reverse.contains(&word) {
            self.motor.run = !tripped;
            self.motor.reverse = codes.run_reverse.contains(&word);
            self.motor.coast = false;
        } else if codes.stop.contains(&word) {
            self.motor.run = false;
        } else if codes.coast.contains(&word) {
            self.motor.run = false;
            self.motor.coast = true;
            self.motor.output = 0.0;
        }
        self.motor.last_word = word;
        self.refresh();
    }

    /// Whether a write of the register with this id changes the command: the command word,
    /// or a register holding one of its bits (or a bit making the frequency command
    /// effective).
    fn commands(&self, behaviour: &Behaviour, id: &str) -> bool {
        let command = &behaviour.command;
        if self.served(command.register) == id {
            return true;
        }
        let single = [
            Some(command.run),
            command.run_reverse,
            command.reverse,
            command.reset,
            command.coast,
        ];
        single
            .into_iter()
            .flatten()
            .chain(command.require.iter().copied())
            .chain(behaviour.frequency.require.iter().copied())
            .any(|bit| bit.register.is_some_and(|own| self.served(own) == id))
    }

    /// The frequency command in force: the command register's value when the command word
    /// makes it effective, else 0; a percentage command as the frequency it stands for.
    pub(crate) fn target(&self) -> f64 {
        let Some(behaviour) = self.behaviour() else {
            return 0.0;
        };
        let frequency = &behaviour.frequency;
        let word = self.command_word(behaviour);
        if !self.all_act(frequency.require, word) {
            return 0.0;
        }
        let command = self.value_of(self.served(frequency.command)).unwrap_or(0.0);
        match frequency.percent_of {
            Some(full) => command * self.amount(full) / 100.0,
            None => command,
        }
    }

    /// Runs the motor model for `elapsed` of simulated time.
    pub(crate) fn step(&mut self, elapsed: Duration) {
        let Some(behaviour) = self.behaviour() else {
            return;
        };
        let frequency = &behaviour.frequency;
        let goal = if self.motor.run && !self.motor.coast && self.motor.trip.is_none() {
            let target = self.target();
            if self.motor.reverse {
                -target
            } else {
                target
            }
        } else {
            0.0
        };
        let span = self.amount(frequency.span).abs().max(f64::EPSILON);
        let output = self.motor.output;
        // Away from zero: accelerating; towards zero (or across it): decelerating.
        let accelerating = goal.abs() > output.abs() && goal * output >= 0.0;
        let time = if accelerating {
            self.amount(frequency.acceleration)
        } else {
            self.amount(frequency.deceleration)
        };
        let change = if time <= 0.0 {
            f64::INFINITY
        } else {
            span / time * elapsed.as_secs_f64()
        };
        self.motor.output = if (goal - output).abs() <= change {
            goal
        } else {
            output + change.copysign(goal - output)
        };
        self.refresh();
    }

    /// A raw value was written to the register `info`: a command word (or a register
    /// holding one of its bits) acts, and a value the behaviour model names resets the
    /// drive.
    pub(crate) fn value_written(&mut self, info: &RegisterInfo, raw: u32) {
        let Some(behaviour) = self.behaviour() else {
            return;
        };
        if self.served(behaviour.command.register) == info.id {
            self.command_written(raw);
        } else if self.commands(behaviour, info.id) {
            self.command_written(self.command_word(behaviour));
        }
        if let Some(reset) = behaviour.command.reset_by_write {
            if self.served(reset.register) == info.id && raw == reset.value {
                self.reset();
            }
        }
        if let Some(clear) = behaviour.trip.clear_by_write {
            if clear.register == info.id && raw == clear.value {
                for slot in self.history_slots(behaviour) {
                    self.set_slot(slot, 0);
                }
            }
        }
    }

    /// Trips the drive with `code`: the output drops to zero, the code goes into the trip
    /// registers and the trip history.
    pub fn inject_trip(&mut self, code: u16) {
        self.hold_trip_data();
        self.motor.trip = Some(code);
        self.motor.run = false;
        self.motor.output = 0.0;
        if let Some(behaviour) = self.behaviour() {
            let history = self.history_slots(behaviour);
            for pair in (1..history.len()).rev() {
                let (from, older) = history[pair - 1];
                let value = older.get(self.storage.get(from, 0));
                self.set_slot(history[pair], value);
            }
            if let Some(&newest) = history.first() {
                self.set_slot(newest, u32::from(code));
            }
        }
        self.refresh();
    }

    /// The trip history's slots with their registers, newest first.
    fn history_slots(&self, behaviour: &Behaviour) -> Vec<(&'static RegisterInfo, TripSlot)> {
        behaviour
            .trip
            .history
            .iter()
            .filter_map(|slot| self.drive.register(slot.register).map(|info| (info, *slot)))
            .collect()
    }

    fn set_slot(&mut self, (info, slot): (&'static RegisterInfo, TripSlot), value: u32) {
        let word = self.storage.get(info, 0);
        self.storage.set(info, 0, slot.put(word, value), false);
    }

    /// Copies each live register into the register holding its value at a trip
    /// (`held_at_trip_of`), as the drive does at the moment it trips.
    fn hold_trip_data(&mut self) {
        for held in self.drive.registers {
            let Some(live) = held
                .held_at_trip_of
                .and_then(|code| self.drive.register(code))
            else {
                continue;
            };
            let raw = self.storage.get(live, 0);
            self.storage.set(held, 0, raw, false);
        }
    }

    /// A fault reset: clears a trip, and parameters that take effect after a reset take
    /// their new values.
    pub fn reset(&mut self) {
        self.motor.trip = None;
        self.motor.run = false;
        self.storage.take_effect(self.drive.registers);
        self.refresh();
    }

    /// The trip code while the drive is tripped.
    pub fn trip(&self) -> Option<u16> {
        self.motor.trip
    }

    /// Writes the monitors and status words from the motor state; held registers keep the
    /// value they are held at.
    pub(crate) fn refresh(&mut self) {
        self.follow_station_register();
        self.follow_model();
        self.show_held();
    }

    /// Writes the monitors and status words from the motor state.
    fn follow_model(&mut self) {
        let Some(behaviour) = self.behaviour() else {
            return;
        };
        let running = self.is_running();
        let output = self.motor.output;
        let target = self.target();
        let tripped = self.motor.trip.is_some();
        let monitor = |drive: &mut VirtualDrive, id: &str, value: f64| {
            if let Some(info) = drive.drive.register(id) {
                // Registers live except while tripped keep their value during a trip.
                // A monitor whose scale another register chooses shows the value in it.
                if !(tripped && info.live_except_while_tripped) {
                    let raw = raw_of(drive.scaled(info), value);
                    drive.storage.set(info, 0, raw, false);
                }
            }
        };
        for id in behaviour.frequency.output {
            monitor(self, id, output.abs());
        }
        for id in behaviour.frequency.reference {
            monitor(self, id, target);
        }
        let mut overloaded = false;
        if let Some(current) = &behaviour.current {
            let span = self
                .amount(behaviour.frequency.span)
                .abs()
                .max(f64::EPSILON);
            let value = if running {
                current.at_zero + (current.at_span - current.at_zero) * output.abs() / span
            } else {
                0.0
            };
            for id in current.registers {
                monitor(self, id, value);
            }
            overloaded = running
                && current
                    .overload
                    .is_some_and(|level| value >= self.amount(level) - 1e-9);
        }
        let detected = running
            && behaviour
                .frequency
                .detection
                .is_some_and(|level| output.abs() >= self.amount(level) - 1e-9);
        let code = f64::from(self.motor.trip.unwrap_or(0));
        for id in behaviour.trip.code {
            monitor(self, id, code);
        }
        // Read-only registers a conversion computes from other registers alone.
        for conversion in self.drive.conversions {
            let Some(result) = conversion.result else {
                continue;
            };
            let derived = self.drive.register(result).is_some_and(|info| {
                info.access == crate::kinds::Access::ReadOnly
                    && conversion
                        .inputs
                        .iter()
                        .all(|input| input.register.is_some())
            });
            if derived {
                if let Some(value) = self.convert(conversion.id, &[]) {
                    monitor(self, result, value);
                }
            }
        }
        let status = &behaviour.status;
        let reverse = running && output < 0.0 || self.motor.reverse;
        let reached = running && (output.abs() - target).abs() < 1e-6 && target > 0.0;
        let roles: [(&[Bit], bool); 9] = [
            (status.always, true),
            (status.running, running),
            (status.reverse, reverse),
            (status.forward, running && !reverse),
            (status.at_reference, reached),
            (status.tripped, self.motor.trip.is_some()),
            (status.overload, overloaded),
            (status.frequency_detected, detected),
            (status.enabled, !self.motor.coast),
        ];
        // The status words' bits, built from nothing; a bit in a register of its own (a
        // status coil) is set or cleared there.
        let mut word = 0u32;
        let mut own: Vec<(&'static str, Bit, bool)> = Vec::new();
        for (bits, on) in roles {
            for bit in bits {
                match bit.register {
                    Some(id) => own.push((id, *bit, on)),
                    None => word = bit.apply(word, on),
                }
            }
        }
        for id in status.registers {
            if let Some(info) = self.drive.register(id) {
                self.storage.set(info, 0, word, false);
            }
        }
        // A bit of its own is cleared before its roles are applied, as the words are.
        for (id, bit, _) in &own {
            if let Some(info) = self.drive.register(id) {
                let cleared = self.storage.get(info, 0) & !bit.mask;
                self.storage.set(info, 0, cleared, false);
            }
        }
        for (id, bit, on) in own {
            if let Some(info) = self.drive.register(id) {
                let value = bit.apply(self.storage.get(info, 0), on);
                self.storage.set(info, 0, value, false);
            }
        }
        if let Some(state) = status.state {
            let value = match (tripped, running, reverse) {
                (true, _, _) => state.tripped,
                (false, true, false) => state.forward,
                (false, true, true) => state.reverse,
                (false, false, _) => state.stopped,
            };
            if let Some(info) = self.drive.register(state.register) {
                self.storage.set(info, 0, value, false);
            }
        }
        if !tripped {
            self.follow_live_registers();
        }
    }

    /// Copies each live register into its held copy where the copy is also marked live
    /// except while tripped (`held_at_trip_of` with `live_except_while_tripped`): such a
    /// copy follows its live register between trips and keeps the trip's value while tripped.
    fn follow_live_registers(&mut self) {
        for held in self.drive.registers {
            if !held.live_except_while_tripped {
                continue;
            }
            let Some(live) = held
                .held_at_trip_of
                .and_then(|code| self.drive.register(code))
            else {
                continue;
            };
            let raw = self.storage.get(live, 0);
            self.storage.set(held, 0, raw, false);
        }
    }
}
