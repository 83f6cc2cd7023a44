//! The control profile on a station: run, set the speed, stop, coast, reset and read the
//! state of any drive with control roles, through its one-drive session. Writes go out in
//! the order the drive needs (the operation mode first where commands need one, the speed
//! before the run command, bits held by other registers before the word), to RAM where the
//! protocol has RAM writes; a speed is checked against the register's range and the
//! bounds other registers set before anything is sent; running while tripped is refused.

use super::error::ControlError;
use super::roles::{MissingRoles, Roles};
use super::state::{registers, DriveState, Readings};
use super::steps::{steps, Action, Direction, Step};
use crate::session::Session;
use crate::session_error::SessionError;
use crate::storage;
use crate::write_value::checked_value;
use std::collections::HashMap;
use vfd_runtime::behaviour::Amount;
use vfd_runtime::units::raw_to_scaled;
use vfd_runtime::RegisterInfo;

/// A station under the control profile.
pub struct Control<'s> {
    session: &'s mut Session,
    roles: Roles,
    /// How far the output may be from the set point and still count as at speed, in the
    /// speed command's unit, where the drive has no at-speed bit of its own.
    pub tolerance: f64,
    /// Writes sent so far by operations (each register write counting once).
    pub writes: usize,
}

impl<'s> Control<'s> {
    /// The control profile of the drive `session` talks to, or the roles it lacks.
    pub fn new(session: &'s mut Session) -> Result<Control<'s>, MissingRoles> {
        let roles = Roles::of(session.drive)?;
        Ok(Control {
            session,
            roles,
            tolerance: 0.5,
            writes: 0,
        })
    }

    /// The drive's roles.
    pub fn roles(&self) -> &Roles {
        &self.roles
    }

    /// The session (for reads and writes beyond the profile).
    pub fn session(&mut self) -> &mut Session {
        self.session
    }

    /// Reads what the state is judged from (the registers this port can read) and judges it.
    pub fn state(&mut self) -> Result<DriveState, SessionError> {
        let mut raw: HashMap<&'static str, u32> = HashMap::new();
        for info in registers(&self.roles) {
            if !self.session.can_read(info) {
                continue;
            }
            let value = self.session.read(info)?;
            if let Some(r) = value.raw {
                raw.insert(info.id, r);
            }
        }
        let percent_of = self.percent_of()?;
        let lookup = |id: &str| raw.get(id).copied();
        Ok(DriveState::judge(
            &self.roles,
            &Readings {
                raw: &lookup,
                percent_of,
            },
            self.tolerance,
        ))
    }

    /// What a percentage speed command's 100 % stands for now (read where a register
    /// sets it), where the speed command is one.
    fn percent_of(&mut self) -> Result<Option<f64>, SessionError> {
        match self.roles.percent_of {
            None => Ok(None),
            Some(Amount::Value(full)) => Ok(Some(full)),
            Some(Amount::Register(id)) => {
                let Some(info) = self.roles.drive.register(id) else {
                    return Ok(None);
                };
                let value = self.session.read(info)?;
                Ok(value.raw.map(|raw| raw_to_scaled(raw, info)))
            }
        }
    }

    /// The speed command's value for `speed`: where the command is a percentage of a
    /// frequency, a frequency (`30`, `30 Hz`) becomes its percentage; a percentage (`50%`)
    /// and any other command's value are the command's own.
    fn speed_value(&mut self, speed: &str) -> Result<String, ControlError> {
        let text = speed.trim();
        if text.ends_with('%') {
            return Ok(text.to_owned());
        }
        let Some(full) = self.percent_of()? else {
            return Ok(text.to_owned());
        };
        let number = text
            .strip_suffix("Hz")
            .unwrap_or(text)
            .trim()
            .parse::<f64>()
            .map_err(|_| {
                ControlError::Session(SessionError::said(format!(
                    "`{speed}` is not a frequency (e.g. `30` or `30 Hz`, or a percentage such as `50%`)"
                )))
            })?;
        if full <= 0.0 {
            return Err(ControlError::Session(SessionError::said(format!(
                "the frequency 100 % stands for is {full}: a speed in Hz cannot be commanded"
            ))));
        }
        Ok(format!("{}", number * 100.0 / full))
    }

    /// Runs the motor in `direction` at `speed` (`30`, `30 Hz`: in the speed command's
    /// unit, or in Hz where the command is a percentage of a frequency, which `50%` then
    /// gives directly), after checking the speed and that the drive is not tripped.
    pub fn run(&mut self, direction: Direction, speed: &str) -> Result<(), ControlError> {
        let plan = self.plan(Action::Run(direction))?;
        let state = self.state()?;
        if state.tripped {
            return Err(ControlError::Tripped(state.trip));
        }
        let speed = self.speed_value(speed)?;
        let (info, raw) = checked_value(self.session, self.roles.speed, &speed)?;
        self.set_up()?;
        self.write(info, raw)?;
        self.carry_out(&plan)
    }

    /// Changes the speed (the motor keeps running or stays stopped).
    pub fn set_speed(&mut self, speed: &str) -> Result<(), ControlError> {
        let speed = self.speed_value(speed)?;
        let (info, raw) = checked_value(self.session, self.roles.speed, &speed)?;
        self.set_up()?;
        self.write(info, raw)
    }

    /// Stops the motor (ramping down). Always allowed, tripped or not.
    pub fn stop(&mut self) -> Result<(), ControlError> {
        let plan = self.plan(Action::Stop)?;
        self.carry_out(&plan)
    }

    /// Coasts the motor to a stop, where the drive can.
    pub fn coast(&mut self) -> Result<(), ControlError> {
        let plan = self.plan(Action::Coast)?;
        self.carry_out(&plan)
    }

    /// Resets a trip, where the drive can on command.
    pub fn reset(&mut self) -> Result<(), ControlError> {
        let plan = self.plan(Action::Reset)?;
        self.carry_out(&plan)
    }

    /// The steps of `action`, or the role the drive lacks for it.
    fn plan(&self, action: Action) -> Result<Vec<Step>, ControlError> {
        steps(&self.roles, action).ok_or(ControlError::Unsupported {
            drive: self.roles.drive.id,
            role: match action {
                Action::Run(Direction::Reverse) => "reverse",
                Action::Run(Direction::Forward) => "run",
                Action::Stop => "stop",
                Action::Coast => "coast",
                Action::Reset => "reset",
            },
        })
    }

    /// The operation mode commands need, written where the drive is in another.
    fn set_up(&mut self) -> Result<(), ControlError> {
        let Some(mode) = self.roles.mode else {
            return Ok(());
        };
        let Some(info) = self.roles.drive.register(mode.register) else {
            return Ok(());
        };
        let now = self.session.read(info)?.raw;
        match (now, mode.values.first()) {
            (Some(now), _) if mode.values.contains(&now) => Ok(()),
            (_, Some(&wanted)) => self.write(info, wanted),
            (_, None) => Ok(()),
        }
    }

    fn carry_out(&mut self, plan: &[Step]) -> Result<(), ControlError> {
        for step in plan {
            match *step {
                Step::Write { register, raw } => self.write(register, raw)?,
                Step::Pulse {
                    register,
                    raw,
                    after,
                } => {
                    self.write(register, raw)?;
                    self.write(register, after)?;
                }
                Step::Bit { register, bit, on } => {
                    let now = if self.session.can_read(register) {
                        self.session.read(register)?.raw.unwrap_or(0)
                    } else {
                        0
                    };
                    self.write(register, bit.apply(now, on))?;
                }
            }
        }
        Ok(())
    }

    /// Writes `raw` to `info`: to RAM where the protocol has a RAM write of it, else
    /// persistently (the only write it has).
    fn write(&mut self, info: &'static RegisterInfo, raw: u32) -> Result<(), ControlError> {
        let info = self.session.on_port(info);
        let persist = !storage::writes(self.session.protocol, info).ram;
        self.session.write(info, raw, persist)?;
        self.writes += 1;
        Ok(())
    }
}
