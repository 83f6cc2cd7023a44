//! A drive's state as the control profile reports it, judged from what was read (sans
//! I/O): running, direction, output frequency, set point, at speed, tripped with the trip
//! code's name, output current.

use super::roles::Roles;
use super::steps::Direction;
use serde::Serialize;
use vfd_runtime::behaviour::Bit;
use vfd_runtime::units::raw_to_scaled;
use vfd_runtime::RegisterInfo;

/// The present trip: its code and the manual's name for it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Trip {
    /// The code as the drive shows it.
    pub code: u32,
    /// Its identifier in the description (`oc1`), empty where the manual's table lacks it.
    pub id: String,
    /// The manual's name for it (English, then the Chinese name where the manual gives one).
    pub name: String,
}

/// What a drive is doing.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DriveState {
    /// The drive's id.
    pub drive: String,
    /// The motor runs (run commanded, or the output not yet at zero).
    pub running: bool,
    /// Its direction, where the drive shows it.
    pub direction: Option<Direction>,
    /// The output frequency, in the speed command's unit.
    pub output: Option<f64>,
    /// The set point in use.
    pub set_point: Option<f64>,
    /// The unit of both (`Hz`, `%`).
    pub unit: String,
    /// Running at the set point: the drive's own status bit where it has one, else the
    /// output within the tolerance asked of the set point.
    pub at_speed: bool,
    /// The drive is tripped.
    pub tripped: bool,
    /// The present trip, where the drive shows its code.
    pub trip: Option<Trip>,
    /// The output current, where described.
    pub current: Option<f64>,
    /// The current's unit.
    pub current_unit: String,
}

/// What the state is judged from: the raw words read, by register id (`None`: not read).
pub struct Readings<'a> {
    /// Raw value of a register by id.
    pub raw: &'a dyn Fn(&str) -> Option<u32>,
    /// The frequency a percentage speed command's 100 % stands for, where it is one.
    pub percent_of: Option<f64>,
}

impl DriveState {
    /// The state `readings` show on a drive with `roles`; at speed within `tolerance` (in
    /// the speed command's unit) where the drive has no at-speed bit.
    pub fn judge(roles: &Roles, readings: &Readings<'_>, tolerance: f64) -> DriveState {
        let raw = readings.raw;
        let any = |bits: &[Bit]| -> Option<bool> {
            let mut seen = None;
            for bit in bits {
                // A bit of the status words (the first one read), or of a register of its
                // own.
                let word = match bit.register {
                    Some(id) => raw(id),
                    None => roles.status.iter().find_map(|id| raw(id)),
                };
                if let Some(word) = word {
                    seen = Some(seen.unwrap_or(false) | bit.is_active(word));
                }
            }
            seen
        };
        let scaled = |info: &RegisterInfo| raw(info.id).map(|r| raw_to_scaled(r, info));
        let state_code = roles.state.and_then(|s| raw(s.register).map(|r| (s, r)));
        let output = roles.output.and_then(scaled);
        let set_point = scaled(roles.set_point).map(|set| {
            // A percentage command's set point, as the frequency it stands for.
            match (
                readings.percent_of,
                std::ptr::eq(roles.set_point, roles.speed),
            ) {
                (Some(full), true) => set * full / 100.0,
                _ => set,
            }
        });
        // Where no status word could be read (a drive that shows its status only in the
        // reply to a command), the output shows whether the motor turns.
        let running = match (state_code, any(roles.running)) {
            (Some((s, r)), _) => s.shows_running(r),
            (None, Some(bit)) => bit,
            (None, None) => output.is_some_and(|out| out != 0.0),
        };
        let direction = match state_code {
            Some((s, r)) if r == s.reverse => Some(Direction::Reverse),
            Some((s, r)) if r == s.forward => Some(Direction::Forward),
            _ => match (any(roles.reverse), any(roles.forward)) {
                (Some(true), _) => Some(Direction::Reverse),
                (Some(false), _) | (None, Some(true)) => Some(Direction::Forward),
                (None, _) => None,
            },
        };
        let trip_raw = roles
            .trip_code
            .and_then(|info| raw(info.id).map(|r| (info, r)));
        let tripped = match (state_code, any(roles.tripped)) {
            (Some((s, r)), _) if r == s.tripped => true,
            (_, Some(bit)) => bit,
            _ => trip_raw.is_some_and(|(_, r)| r != 0),
        };
        let trip = trip_raw.filter(|_| tripped).map(|(info, code)| {
            let found = info
                .codes
                .and_then(|codes| u16::try_from(code).ok().and_then(|c| codes.find(c)));
            Trip {
                code,
                id: found.map_or(String::new(), |c| c.id.to_owned()),
                name: match found {
                    Some(c) if c.name_zh.is_empty() => c.name.to_owned(),
                    Some(c) => format!("{} / {}", c.name, c.name_zh),
                    None => format!("code {code} (not in the manual's table)"),
                },
            }
        });
        let at_speed = running
            && match any(roles.at_speed) {
                Some(bit) => bit,
                None => match (output, set_point) {
                    (Some(out), Some(set)) => (out.abs() - set.abs()).abs() <= tolerance,
                    _ => false,
                },
            };
        DriveState {
            drive: roles.drive.id.to_owned(),
            running,
            direction: direction.filter(|_| running),
            output,
            set_point,
            unit: match (roles.output, readings.percent_of) {
                (Some(output), Some(_)) => output.unit_symbol().to_owned(),
                _ => roles.speed.unit_symbol().to_owned(),
            },
            at_speed,
            tripped,
            trip,
            current: roles.current.and_then(scaled),
            current_unit: roles
                .current
                .map_or(String::new(), |c| c.unit_symbol().to_owned()),
        }
    }
}

/// The registers a state is judged from, each once: status words, the state register,
/// bits held elsewhere, the output, the set point, the trip code, the current.
pub fn registers(roles: &Roles) -> Vec<&'static RegisterInfo> {
    let drive = roles.drive;
    let mut ids: Vec<&str> = roles.status.to_vec();
    ids.extend(roles.state.map(|s| s.register));
    for bits in [
        roles.running,
        roles.reverse,
        roles.forward,
        roles.at_speed,
        roles.tripped,
    ] {
        ids.extend(bits.iter().filter_map(|b| b.register));
    }
    let mut list: Vec<&'static RegisterInfo> =
        ids.iter().filter_map(|id| drive.register(id)).collect();
    list.extend(roles.output);
    list.push(roles.set_point);
    list.extend(roles.trip_code);
    list.extend(roles.current);
    let mut unique: Vec<&'static RegisterInfo> = Vec::new();
    for info in list {
        if !unique.iter().any(|u| std::ptr::eq(*u, info)) {
            unique.push(info);
        }
    }
    unique
}
