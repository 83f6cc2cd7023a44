//! The one write check: whether a write may be sent, asked the same way by `vfd write`,
//! `vfd restore`, `vfd serve` and any program. Each check refuses with a typed
//! [`Refusal`] ([`Reason`]: what was refused; a message naming the register, and a hint),
//! before anything is sent:
//! - [`writable`]: the register's access (read-only registers, text) and storage (a
//!   RAM-only register written persistently);
//! - [`allowed`]: a plant's allow-list (the `write:` list of a station);
//! - [`in_range`]: the value as people write it, in the register's unit and range;
//! - [`within_bounds`]: the bounds other registers set at run time (FH for the frequency
//!   command), read from the drive;
//! - [`combinations`]: the combinations of values the manual forbids, the other registers
//!   read from the drive.
//!
//! The checks that need the drive's present values take a `read` function (a register in,
//! its raw value out when it could be read): the caller reads over its station. A register
//! that cannot be read fulfils no bound and no condition.

use crate::values;
use std::fmt;
use vfd_runtime::units::raw_to_scaled;
use vfd_runtime::{Access, DataType, DriveInfo, RegisterInfo};

/// What a write was refused for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Reason {
    /// The register is read-only (or text, which is only read).
    ReadOnly,
    /// A persistent write of a register kept in RAM only.
    RamOnly,
    /// The plant's allow-list does not name the register.
    NotAllowed,
    /// The value is not one the register takes (its unit, its range).
    Range,
    /// The value is beyond a bound another register sets now.
    Bound,
    /// The value would make a combination the manual forbids.
    Forbidden,
}

/// A write refused before anything was sent.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Refusal {
    reason: Reason,
    message: String,
    hint: Option<String>,
}

impl Refusal {
    fn new(reason: Reason, message: impl Into<String>, hint: impl Into<String>) -> Refusal {
        Refusal {
            reason,
            message: message.into(),
            hint: Some(hint.into()),
        }
    }

    /// What was refused.
    pub fn reason(&self) -> Reason {
        self.reason
    }

    /// Why, for people, naming the register (one line, without the hint).
    pub fn message(&self) -> &str {
        &self.message
    }

    /// What to do about it.
    pub fn hint(&self) -> Option<&str> {
        self.hint.as_deref()
    }

    /// The message and the hint.
    pub fn into_parts(self) -> (String, Option<String>) {
        (self.message, self.hint)
    }
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Refusal {}

impl From<Refusal> for crate::Error {
    fn from(refusal: Refusal) -> crate::Error {
        let (message, hint) = refusal.into_parts();
        crate::Error::new(crate::ErrorKind::Refused, message).with_hint_or_none(hint)
    }
}

/// Refuses writes the register does not allow: read-only registers and text, and a
/// persistent write (`persist`) of a register kept in RAM only.
pub fn writable(info: &RegisterInfo, persist: bool) -> Result<(), Refusal> {
    if info.access == Access::ReadOnly || info.data_type == DataType::Text {
        return Err(Refusal::new(
            Reason::ReadOnly,
            format!("{} is read-only", info.label()),
            format!(
                "the manual lists it as read-only (`vfd info DRIVE {}` shows its access); read it with `vfd read`",
                info.code
            ),
        ));
    }
    if persist && info.ram_only {
        return Err(Refusal::new(
            Reason::RamOnly,
            format!(
                "{} is RAM-only: it cannot be written persistently",
                info.label()
            ),
            "leave out --persist",
        ));
    }
    Ok(())
}

/// The entry of `allow` (a station's allow-list) that allows `info` (the same register,
/// on any port); refused naming the station (`place`, e.g. `bus/drive`) and what the list
/// allows.
pub fn allowed(
    allow: &[&'static RegisterInfo],
    info: &RegisterInfo,
    place: &str,
) -> Result<usize, Refusal> {
    allow
        .iter()
        .position(|allowed| same_register(allowed, info))
        .ok_or_else(|| {
            let codes: Vec<&str> = allow.iter().map(|a| a.code).collect();
            Refusal::new(
                Reason::NotAllowed,
                format!(
                    "{} may not be written on {place}: the plant file does not allow it; nothing was sent",
                    info.label()
                ),
                if codes.is_empty() {
                    "the plant file allows no writes to this drive (its `write:` list)".to_owned()
                } else {
                    format!("its `write:` list allows {}", codes.join(", "))
                },
            )
        })
}

/// Whether two register entries are the same register (or copies of it on a port).
pub fn same_register(a: &RegisterInfo, b: &RegisterInfo) -> bool {
    a.code == b.code || (a.space == b.space && a.address == b.address)
}

/// The raw word `text` writes to `info` (`60Hz`, `C400h`, a code's name), refused when
/// it is not one the register takes; `drive_name` names the drive in the hint, as a
/// command line names it.
pub fn in_range(info: &'static RegisterInfo, text: &str, drive_name: &str) -> Result<u32, Refusal> {
    values::parse(info, text).map_err(|message| {
        Refusal::new(
            Reason::Range,
            message,
            format!(
                "nothing was sent; `vfd info {drive_name} {}` shows the range",
                info.code
            ),
        )
    })
}

/// Refuses `raw` for `info` beyond a bound another register sets at run time (FH for the
/// frequency command), reading that register with `read` first.
pub fn within_bounds(
    drive: &DriveInfo,
    info: &'static RegisterInfo,
    raw: u32,
    mut read: impl FnMut(&'static RegisterInfo) -> Option<u32>,
) -> Result<(), Refusal> {
    let value = raw_to_scaled(raw, info);
    for (bound, above) in [(info.min_bound, false), (info.max_bound, true)] {
        let Some(code) = bound else { continue };
        let Some(other) = drive.register(code) else {
            continue;
        };
        let Some(limit_raw) = read(other) else {
            continue;
        };
        let limit = raw_to_scaled(limit_raw, other);
        let beyond = if above { value > limit } else { value < limit };
        if beyond {
            return Err(Refusal::new(
                Reason::Bound,
                format!(
                    "{}: {} is {} {} ({}) = {} now; nothing was written",
                    info.label(),
                    values::scaled(info, raw),
                    if above { "above" } else { "below" },
                    other.code,
                    other.name,
                    values::scaled(other, limit_raw)
                ),
                format!("the range is {}", values::range_text(drive, info)),
            ));
        }
    }
    Ok(())
}

/// Refuses `raw` for `info` where it would make a combination of values the manual
/// forbids (the description's `forbidden_combinations`): the other registers of each
/// combination `info` is in are read with `read` first, once each.
pub fn combinations(
    drive: &DriveInfo,
    info: &'static RegisterInfo,
    raw: u32,
    mut read: impl FnMut(&'static RegisterInfo) -> Option<u32>,
) -> Result<(), Refusal> {
    let mut known: Vec<(&'static str, u32)> = Vec::new();
    for combination in drive.combinations_of(info) {
        for condition in combination.when {
            if condition.register == info.code
                || known.iter().any(|(code, _)| *code == condition.register)
            {
                continue;
            }
            let Some(other) = drive.register(condition.register) else {
                continue;
            };
            if let Some(value) = read(other) {
                known.push((condition.register, value));
            }
        }
    }
    drive
        .check_combinations(info, raw, |code| {
            known.iter().find(|(c, _)| *c == code).map(|(_, v)| *v)
        })
        .map_err(|error| {
            Refusal::new(
                Reason::Forbidden,
                error.to_string(),
                "change the other register first (most take effect after a reset), or write a value the rule allows",
            )
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn registers() -> impl Iterator<Item = (&'static DriveInfo, &'static RegisterInfo)> {
        vfd_drives::ALL_DRIVES
            .iter()
            .flat_map(|d| d.registers.iter().map(move |r| (*d, *r)))
    }

    #[test]
    fn read_only_and_ram_only_registers_are_refused_by_reason() {
        let (_, read_only) = registers()
            .find(|(_, r)| r.access == Access::ReadOnly)
            .expect("a read-only register");
        let refusal = writable(read_only, false).unwrap_err();
        assert_eq!(refusal.reason(), Reason::ReadOnly);
        assert!(refusal.message().contains(read_only.code));
        let (_, ram_only) = registers()
            .find(|(_, r)| {
                r.ram_only && r.access != Access::ReadOnly && r.data_type != DataType::Text
            })
            .expect("a RAM-only register");
        assert!(writable(ram_only, false).is_ok());
        assert_eq!(
            writable(ram_only, true).unwrap_err().reason(),
            Reason::RamOnly
        );
        let error: crate::Error = writable(ram_only, true).unwrap_err().into();
        assert_eq!(error.kind(), crate::ErrorKind::Refused);
        assert!(!error.kind().sent());
    }

    #[test]
    fn the_allow_list_names_what_it_allows() {
        let (_, first) = registers().next().unwrap();
        let (_, other) = registers().find(|(_, r)| r.code != first.code).unwrap();
        assert_eq!(allowed(&[first], first, "bus/drive"), Ok(0));
        let refusal = allowed(&[first], other, "bus/drive").unwrap_err();
        assert_eq!(refusal.reason(), Reason::NotAllowed);
        assert!(refusal.message().contains("on bus/drive"));
        assert_eq!(
            refusal.hint(),
            Some(format!("its `write:` list allows {}", first.code).as_str())
        );
        assert!(allowed(&[], other, "b/d")
            .unwrap_err()
            .hint()
            .unwrap()
            .contains("no writes"));
    }

    #[test]
    fn a_bound_another_register_sets_is_read_and_kept() {
        let (drive, bounded) = registers()
            .find(|(d, r)| r.max_bound.is_some_and(|code| d.register(code).is_some()))
            .expect("a register bounded by another");
        let bound = drive.register(bounded.max_bound.unwrap()).unwrap();
        // The bound reads as the bounded register's raw 100 in its own scale.
        let limit = vfd_runtime::units::scaled_to_raw(raw_to_scaled(100, bounded), bound);
        let Ok(limit) = limit else { return };
        let mut asked = Vec::new();
        let refusal = within_bounds(drive, bounded, 101, |r| {
            asked.push(r.code);
            Some(limit)
        })
        .unwrap_err();
        assert_eq!(asked, [bound.code]);
        assert_eq!(refusal.reason(), Reason::Bound);
        assert!(within_bounds(drive, bounded, 100, |_| Some(limit)).is_ok());
        // A bound that cannot be read bounds nothing.
        assert!(within_bounds(drive, bounded, 101, |_| None).is_ok());
    }
}
